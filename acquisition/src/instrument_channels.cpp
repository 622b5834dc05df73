#include "instrument_channels.hpp"

namespace tocd::acquisition {

InstrumentChannels::InstrumentChannels(InstrumentSet set) {
  if (set.tester) tester = std::make_unique<TesterChannel>(std::move(set.tester));
  if (set.power_meter) power = std::make_unique<PowerChannel>(std::move(set.power_meter));
  if (set.vacuum) vacuum = std::make_unique<VacuumChannel>(std::move(set.vacuum));
}

void InstrumentChannels::configure(const Protocol& p, double baseline_W) {
  // The settle windows keep two windows' worth of readings and a second more.
  const double keep_s = 2.0 * p.settle.window_s + 1.0;
  if (tester) {
    tester->configure(p.rates.tester_Hz, true);
    tester->set_run(p.contact_position_mm, p.interlocks.max_load_N, keep_s);
  }
  if (power) {
    power->configure(p.rates.power_Hz, true);
    power->set_run(baseline_W, p.interlocks.power_over_range_pauses);
  }
  if (vacuum) {
    vacuum->configure(p.rates.pressure_Hz, p.kind == StepKind::vacuum);
    vacuum->set_run(p.interlocks.vacuum_loss_kPa, keep_s);
  }
}

std::vector<InstrumentChannel*> InstrumentChannels::present() const {
  std::vector<InstrumentChannel*> out;
  if (tester) out.push_back(tester.get());
  if (power) out.push_back(power.get());
  if (vacuum) out.push_back(vacuum.get());
  return out;
}

}  // namespace tocd::acquisition
