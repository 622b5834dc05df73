// Every simulated instrument of the rig on its real transport, sharing one clock and one sample.
#include "tocd/mocks/simulated_lab.hpp"

#include <cmath>

#include "tocd/core/error.hpp"
#include "tocd/mocks/power_meter_twin.hpp"
#include "tocd/mocks/sim_clock.hpp"
#include "tocd/mocks/tester_twin.hpp"
#include "tocd/mocks/vacuum_twin.hpp"

namespace tocd::mocks {

SimulatedLabOptions simulated_lab_options(const SampleTruth& truth) {
  SimulatedLabOptions o;
  o.relaxation_fraction = truth.relaxation_fraction;
  o.relaxation_time_s = truth.relaxation_time_s;
  o.delayed_clearing = truth.delayed_clearing;
  o.delayed_clearing_time_s = truth.delayed_clearing_time_s;
  return o;
}

struct SimulatedLab::Impl {
  SimulatedLabOptions opt;
  std::shared_ptr<SimClock> clock;
  std::unique_ptr<TesterTwin> tester;
  std::unique_ptr<VacuumTwin> vacuum;
  std::unique_ptr<PowerMeterTwin> meter;
};

SimulatedLab::SimulatedLab(SimulatedLabOptions opt) : impl_(std::make_unique<Impl>()) {
  if (!opt.tissue) opt.tissue = make_analytic_tissue(2.5);
  if (!(opt.source_power_W >= 0.0)) throw ConfigError("simulated lab: source power must be >= 0 W");
  if (!(opt.delayed_clearing >= 0.0 && opt.delayed_clearing <= 1.0))
    throw ConfigError("simulated lab: delayed clearing must lie in [0, 1]");
  if (!(opt.relaxation_fraction >= 0.0) || !std::isfinite(opt.relaxation_fraction))
    throw ConfigError("simulated lab: relaxation fraction must be finite and >= 0");
  if (!(opt.relaxation_time_s > 0.0) || !(opt.delayed_clearing_time_s > 0.0))
    throw ConfigError("simulated lab: relaxation and delayed clearing times must be > 0 s");
  auto& s = *impl_;
  s.opt = opt;
  s.clock = std::make_shared<SimClock>(opt.clock_factor);

  TesterTwinOptions t;
  t.clock = s.clock;
  t.port = opt.tester_port;
  t.physics.tissue = opt.tissue;
  t.physics.contact_position_mm = opt.contact_position_mm;
  t.physics.seed = opt.seed;
  t.physics.relaxation_fraction = opt.relaxation_fraction;
  t.physics.relaxation_time_s = opt.relaxation_time_s;
  t.physics.drained_time_s = opt.delayed_clearing_time_s;
  s.tester = std::make_unique<TesterTwin>(t);

  if (opt.with_vacuum) {
    VacuumTwinOptions v;
    v.clock = s.clock;
    s.vacuum = std::make_unique<VacuumTwin>(v);
  }
  if (opt.with_power_meter) {
    PowerMeterTwinOptions p;
    p.clock = s.clock;
    p.seed = opt.seed + 1;
    // The light under the slide: source power through the sample at the pin's displacement.
    TesterTwin* tester = s.tester.get();
    const auto tissue = opt.tissue;
    const double source = opt.source_power_W, f = opt.delayed_clearing;
    p.power_W = [tester, tissue, source, f] {
      const double now = tissue->transmission(tester->displacement_mm());
      if (f == 0.0) return source * now;
      return source * ((1.0 - f) * now + f * tissue->transmission(tester->drained_displacement_mm()));
    };
    s.meter = std::make_unique<PowerMeterTwin>(p);
    s.meter->serve_tcp("127.0.0.1", opt.power_meter_port);
  }
}

SimulatedLab::~SimulatedLab() {
  // The meter reads the tester's displacement: stop it first.
  impl_->meter.reset();
  impl_->vacuum.reset();
  impl_->tester.reset();
}

devices::LabConfig SimulatedLab::config() const {
  devices::LabConfig cfg;
  cfg.name = "simulated lab";
  devices::ModbusOptions link;
  link.timeout_s = 0.5;
  link.retries = 2;
  link.backoff_s = 0.01;
  cfg.tester = devices::TesterConfig{impl_->tester->address(), link};
  if (impl_->vacuum) cfg.vacuum = devices::VacuumConfig{impl_->vacuum->address(), link};
  if (impl_->meter) {
    devices::PowerMeterConfig pm;
    pm.transport = devices::PowerMeterConfig::Transport::scpi_tcp;
    const auto a = impl_->meter->tcp_address();
    pm.host = a.host;
    pm.port = a.port;
    pm.timeout_s = 1.0;
    cfg.power_meter = pm;
  }
  return cfg;
}

const SimClock& SimulatedLab::clock() const {
  return *impl_->clock;
}
TesterTwin& SimulatedLab::tester() {
  return *impl_->tester;
}
VacuumTwin* SimulatedLab::vacuum() {
  return impl_->vacuum.get();
}
bool SimulatedLab::has_power_meter() const {
  return impl_->meter != nullptr;
}
PowerMeterTwin* SimulatedLab::power_meter() {
  return impl_->meter.get();
}

void SimulatedLab::inject_tester_fault(const ModbusFault& fault) {
  impl_->tester->inject(fault);
}

void SimulatedLab::inject_vacuum_fault(const ModbusFault& fault) {
  if (!impl_->vacuum) throw ConfigError("simulated lab: no vacuum controller to inject a fault into");
  impl_->vacuum->inject(fault);
}

void SimulatedLab::drop_tester_connections() {
  impl_->tester->drop_connections();
}
void SimulatedLab::trip_load_limit() {
  impl_->tester->trip_load_limit();
}

void SimulatedLab::inject_seal_loss(bool lost) {
  if (!impl_->vacuum) throw ConfigError("simulated lab: no vacuum controller to lose its seal");
  impl_->vacuum->inject_seal_loss(lost);
}

bool SimulatedLab::inject_power_meter_error(int code, const std::string& message) {
  if (!impl_->meter) return false;
  impl_->meter->push_error(code, message);
  return true;
}

bool SimulatedLab::force_power_over_range(bool on) {
  if (!impl_->meter) return false;
  if (on)
    impl_->meter->over_range_readings(1 << 30);
  else
    impl_->meter->clear_faults();
  return true;
}

}  // namespace tocd::mocks
