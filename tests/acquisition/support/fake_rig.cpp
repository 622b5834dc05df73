#include "fake_rig.hpp"

#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/core/error.hpp"
#include "tocd/devices/power_meter_drivers.hpp"
#include "tocd/devices/tester_registers.hpp"
#include "tocd/devices/vacuum_registers.hpp"

namespace tocd::acquisition::testing {

FakeWorld::FakeWorld(double clock_factor, double contact, double thickness)
    : contact_mm(contact), thickness_mm(thickness), clock_factor_(clock_factor), start_ns_(monotonic_ns()) {}

double FakeWorld::now_s() const {
  return static_cast<double>(monotonic_ns() - start_ns_) * 1e-9 * clock_factor_;
}

double FakeWorld::equilibrium_load_N(double d) const {
  return d > 0 ? stiffness_N_per_mm15 * std::pow(d, 1.5) : 0.0;
}

double FakeWorld::transmission(double d, double p) const {
  // Compression and vacuum both clear the tissue; any monotonic law does for the engine.
  return 0.2 + 0.5 * std::max(0.0, d) / thickness_mm + 0.2 * (kAtmosphere_kPa - p) / kAtmosphere_kPa;
}

double FakeWorld::position_mm_locked(double t) const {
  if (t >= arrive_t) return target_mm;
  const double dir = target_mm > pos0_mm ? 1.0 : -1.0;
  return pos0_mm + dir * speed * (t - move_t0);
}

double FakeWorld::position_mm() const {
  std::lock_guard lock(mu);
  return position_mm_locked(now_s());
}

double FakeWorld::load_N() const {
  std::lock_guard lock(mu);
  return raw_load_N_locked() - tare_N;
}

void FakeWorld::tare() {
  std::lock_guard lock(mu);
  tare_N = raw_load_N_locked();
}

double FakeWorld::raw_load_N_locked() const {
  const double t = now_s();
  const double d = position_mm_locked(t) - contact_mm;
  // Viscoelastic: the load runs relax_fraction above equilibrium while the pin moves and
  // relaxes back with relax_tau_s once it stops (continuous at the stop).
  double load = equilibrium_load_N(d) * (1.0 + relax_fraction);
  if (t >= arrive_t)
    load = equilibrium_load_N(d) * (1.0 + relax_fraction * std::exp(-(t - arrive_t) / relax_tau_s));
  return load + extra_load_N + load_cell_offset_N;
}

double FakeWorld::pressure_now_kPa() {
  std::lock_guard lock(mu);
  const double t = now_s();
  const double goal = seal_lost || !pump ? kAtmosphere_kPa : setpoint_kPa;
  pressure_kPa += (goal - pressure_kPa) * (1.0 - std::exp(-(t - pressure_t) / vacuum_tau_s));
  pressure_t = t;
  return pressure_kPa;
}

namespace {

class FakeTester : public devices::MechanicalTester {
 public:
  explicit FakeTester(std::shared_ptr<FakeWorld> w) : w_(std::move(w)) {}
  const devices::InstrumentCapabilities& describe() const override {
    return devices::tester_map::capabilities;
  }
  devices::Identity identity() override { return {"Fake", "Tester", "T-1", "1.0"}; }
  devices::TesterReading read() override {
    ++w_->reads;
    if (const int us = w_->tester_read_delay_us; us > 0)
      std::this_thread::sleep_for(std::chrono::microseconds(us));
    if (w_->fail_tester_reads > 0) {
      --w_->fail_tester_reads;
      throw devices::TimeoutError("fake tester", "read position/load", "timed out after 3 retries");
    }
    devices::TesterReading r;
    const double t = w_->now_s();
    {
      std::lock_guard lock(w_->mu);
      r.position_mm = w_->position_mm_locked(t);
      r.status.moving = t < w_->arrive_t;
      r.status.at_target = !r.status.moving;
    }
    r.load_N = w_->load_N();
    r.status.ready = true;
    return r;
  }
  void move_to(double position_mm, double v) override {
    ++w_->move_calls;
    if (w_->refuse_moves > 0) {
      --w_->refuse_moves;
      throw devices::InstrumentFault("fake tester", "target, velocity, move command",
                                     "refused with Modbus exception 3 (illegal data value)");
    }
    if (position_mm > 0.0) position_mm -= w_->move_short_by_mm;
    std::lock_guard lock(w_->mu);
    const double t = w_->now_s();
    w_->pos0_mm = w_->position_mm_locked(t);
    w_->target_mm = position_mm;
    w_->speed = v;
    w_->move_t0 = t;
    w_->arrive_t = t + std::abs(position_mm - w_->pos0_mm) / v;
  }
  void stop() override {
    ++w_->stop_calls;
    std::lock_guard lock(w_->mu);
    const double t = w_->now_s();
    w_->pos0_mm = w_->target_mm = w_->position_mm_locked(t);
    w_->arrive_t = w_->move_t0 = t;
  }
  void home() override { move_to(0.0, 5.0); }
  void tare_load() override {
    ++w_->tare_calls;
    w_->tare();
  }
  void set_limits(double travel_mm, double load_N) override {
    ++w_->set_limits_calls;
    w_->limit_travel_mm = travel_mm;
    w_->limit_load_N = load_N;
  }
  void clear_fault() override {}

 private:
  std::shared_ptr<FakeWorld> w_;
};

class FakePowerMeter : public devices::PowerMeter {
 public:
  explicit FakePowerMeter(std::shared_ptr<FakeWorld> w) : w_(std::move(w)) {}
  const devices::InstrumentCapabilities& describe() const override {
    return devices::scpi_power_meter_capabilities;
  }
  devices::Identity identity() override { return {"Fake", "PowerMeter", "P-1", "1.0"}; }
  std::string sensor_identity() override { return "fake photodiode"; }
  void set_wavelength_nm(double) override {}
  void set_auto_range(bool) override {}
  void set_averaging(int) override {}
  void zero() override {}
  devices::PowerReading measure() override {
    devices::PowerReading r;
    double p;
    {
      std::lock_guard lock(w_->mu);
      p = w_->pressure_kPa;
    }
    const double T = w_->transmission(w_->position_mm() - w_->contact_mm, p);
    r.power_W = w_->source_W * T * (1.0 + 1e-4 * noise_(rng_));  // 0.01 % read noise
    // As the SCPI driver reports it: over range, and the power +inf (9.9E37 on the wire).
    r.over_range = w_->power_over_range;
    if (r.over_range) r.power_W = std::numeric_limits<double>::infinity();
    if (w_->nan_power_readings > 0) {
      --w_->nan_power_readings;
      r.power_W = std::nan("");
    }
    return r;
  }

 private:
  std::shared_ptr<FakeWorld> w_;
  std::mt19937 rng_{7};
  std::normal_distribution<double> noise_;
};

class FakeVacuum : public devices::VacuumController {
 public:
  explicit FakeVacuum(std::shared_ptr<FakeWorld> w) : w_(std::move(w)) {}
  const devices::InstrumentCapabilities& describe() const override {
    return devices::vacuum_map::capabilities;
  }
  devices::Identity identity() override { return {"Fake", "Vacuum", "V-1", "1.0"}; }
  devices::VacuumReading read() override {
    devices::VacuumReading r;
    r.pressure_kPa = w_->pressure_now_kPa();
    std::lock_guard lock(w_->mu);
    r.setpoint_kPa = w_->setpoint_kPa;
    r.pump_running = w_->pump;
    return r;
  }
  void set_setpoint_kPa(double kPa) override {
    w_->pressure_now_kPa();
    std::lock_guard lock(w_->mu);
    w_->setpoint_kPa = kPa;
  }
  void run_pump(bool on) override {
    w_->pressure_now_kPa();
    std::lock_guard lock(w_->mu);
    w_->pump = on;
  }
  void set_vent(bool) override {}

 private:
  std::shared_ptr<FakeWorld> w_;
};

}  // namespace

InstrumentSet make_fake_instruments(const std::shared_ptr<FakeWorld>& world, bool with_tester,
                                    bool with_vacuum) {
  InstrumentSet s;
  if (with_tester) s.tester = std::make_unique<FakeTester>(world);
  s.power_meter = std::make_unique<FakePowerMeter>(world);
  if (with_vacuum) s.vacuum = std::make_unique<FakeVacuum>(world);
  return s;
}

FakePredictor::~FakePredictor() {
  open_gate();
  for (auto& t : threads_) t.join();
}

std::future<PredictedStep> FakePredictor::predict(const RecordedStep& step) {
  ++calls;
  auto promise = std::make_shared<std::promise<PredictedStep>>();
  auto future = promise->get_future();
  std::lock_guard lock(mu_);
  threads_.emplace_back([this, promise, step] {
    {
      std::unique_lock gate(mu_);
      cv_.wait(gate, [&] { return gate_open_ || cancelled_; });
      if (cancelled_) {
        promise->set_exception(std::make_exception_ptr(tocd::Cancelled("fake prediction cancelled")));
        return;
      }
    }
    if (fail) {
      promise->set_exception(std::make_exception_ptr(tocd::Error("fake simulator failed")));
      return;
    }
    PredictedStep p;
    p.T = step.measured_T * factor_;
    p.T_stderr = 0.001;
    p.config_json = fmt::format(R"({{"fake": true, "displacement_mm": {}}})", step.displacement_mm);
    p.seconds = 0.01;
    if (work.count() > 0) {
      const auto began = std::chrono::steady_clock::now();
      std::this_thread::sleep_for(work);
      p.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    }
    promise->set_value(p);
  });
  return future;
}

void FakePredictor::cancel() noexcept {
  {
    std::lock_guard lock(mu_);
    cancelled_ = true;
  }
  cv_.notify_all();
}

void FakePredictor::close_gate() {
  std::lock_guard lock(mu_);
  gate_open_ = false;
}

void FakePredictor::open_gate() {
  {
    std::lock_guard lock(mu_);
    gate_open_ = true;
  }
  cv_.notify_all();
}

}  // namespace tocd::acquisition::testing
