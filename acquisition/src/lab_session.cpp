// The lab session: the one place where instruments, database, predictor and engine are wired.
#include "tocd/acquisition/lab_session.hpp"

#include "demo_protocol_text.hpp"

namespace tocd::acquisition {

namespace {

std::shared_ptr<StepPredictor> make_predictor(const LabSessionOptions& o) {
  if (o.predictor) return o.predictor;
  if (!o.predict) return nullptr;
  // One FE + MC prediction at a time: the recorded steps come one by one and each prediction
  // uses every core for its Monte Carlo.
  return std::make_shared<SimStepPredictor>(std::make_shared<sim::study::Predictor>(1), *o.predict);
}

EngineOptions with_lab_text(EngineOptions e, const devices::LabConfig& lab) {
  if (e.lab_config_text.empty()) e.lab_config_text = devices::to_toml(lab);
  return e;
}

}  // namespace

InstrumentSet to_instrument_set(devices::LabInstruments lab) {
  return InstrumentSet{std::move(lab.tester), std::move(lab.power_meter), std::move(lab.vacuum)};
}

LabSession::LabSession(db::Database& db, InstrumentSet instruments, LabSessionOptions options,
                       EngineObserver* observer)
    : db_(db),
      engine_(std::make_unique<Engine>(db, std::move(instruments), options.engine, make_predictor(options),
                                       observer)) {}

LabSession::LabSession(db::Database& db, const devices::LabConfig& lab, LabSessionOptions options,
                       EngineObserver* observer)
    : LabSession(db, to_instrument_set(devices::open_lab(lab)),
                 LabSessionOptions{with_lab_text(options.engine, lab), options.predict, options.predictor},
                 observer) {}

std::string_view demo_protocol_text() {
  return kDemoProtocolToml;
}

Protocol demo_protocol() {
  return parse_protocol(std::string(demo_protocol_text()), "protocols/demo.toml");
}

}  // namespace tocd::acquisition
