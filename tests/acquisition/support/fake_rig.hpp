#pragma once

// In-process fakes of the rig's instruments for the run engine's tests: a tester that moves
// at finite speed with a load law that relaxes after each move, a power meter reading
// source power x transmission(displacement or vacuum), a vacuum controller that pumps down
// with a time constant. They share one FakeWorld (simulated clock + fault hooks).

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <random>

#include "tocd/acquisition/engine.hpp"
#include "tocd/devices/instruments.hpp"

namespace tocd::acquisition::testing {

struct FakeWorld {
  explicit FakeWorld(double clock_factor, double contact_mm = 1.0, double thickness_mm = 2.0);

  double now_s() const;  ///< simulated seconds since construction

  // Physics (simulated units).
  double contact_mm;
  double thickness_mm;
  double stiffness_N_per_mm15 = 4.0;  ///< equilibrium load = k d^1.5
  double relax_fraction = 0.2;        ///< load above equilibrium while moving, relaxing with relax_tau_s
  double relax_tau_s = 0.3;
  double source_W = 1e-3;
  double vacuum_tau_s = 0.3;
  static constexpr double kAtmosphere_kPa = 101.3;

  double equilibrium_load_N(double d_mm) const;
  double transmission(double d_mm, double pressure_kPa) const;

  // Fault hooks (set from the test thread at any time).
  std::atomic<double> extra_load_N{0.0};
  std::atomic<double> load_cell_offset_N{0.0};  ///< what the cell reads unloaded until tared
  std::atomic<int> fail_tester_reads{0};
  std::atomic<bool> power_over_range{false};
  std::atomic<bool> seal_lost{false};
  std::atomic<int> refuse_moves{0};           ///< the next N move commands throw (the tester refuses)
  std::atomic<int> nan_power_readings{0};     ///< the next N power readings are NaN
  std::atomic<double> move_short_by_mm{0.0};  ///< moves end this far short of their target
  std::atomic<int> tester_read_delay_us{0};   ///< each tester read takes this long (real time)

  // Counters.
  std::atomic<int> stop_calls{0}, move_calls{0}, reads{0}, tare_calls{0}, set_limits_calls{0};
  std::atomic<double> limit_travel_mm{0.0}, limit_load_N{0.0};  ///< last limits written

  // State (guarded by mu).
  mutable std::mutex mu;
  double pos0_mm = 0, target_mm = 0, speed = 1, move_t0 = 0, arrive_t = 0;
  double pressure_kPa = kAtmosphere_kPa, setpoint_kPa = kAtmosphere_kPa, pressure_t = 0;
  bool pump = false;
  double tare_N = 0;  ///< subtracted from the cell's reading since the last tare

  double position_mm_locked(double t) const;
  double position_mm() const;
  double load_N() const;  ///< what the load cell reports (offset and tare included)
  void tare();
  double pressure_now_kPa();

 private:
  double raw_load_N_locked() const;
  double clock_factor_;
  std::int64_t start_ns_;
};

/// Instruments over a shared world; `with_vacuum` adds the vacuum controller.
InstrumentSet make_fake_instruments(const std::shared_ptr<FakeWorld>& world, bool with_tester = true,
                                    bool with_vacuum = false);

/// A predictor that answers T = measured_T * factor on a thread of its own, after an optional
/// gate opens (so tests can hold predictions back while acquisition goes on).
class FakePredictor : public StepPredictor {
 public:
  explicit FakePredictor(double factor = 1.02) : factor_(factor) {}
  ~FakePredictor() override;
  std::future<PredictedStep> predict(const RecordedStep& step) override;
  /// Every prediction waiting at the gate, and every later one, ends in tocd::Cancelled.
  void cancel() noexcept override;
  void close_gate();
  void open_gate();
  std::atomic<int> calls{0};
  std::atomic<bool> fail{false};  ///< predictions end in an error (a simulator that failed)
  /// How long each prediction works once through the gate (set before the run): its
  /// PredictedStep::seconds is then that time as measured, instead of a nominal 0.01 s.
  std::chrono::milliseconds work{0};

 private:
  double factor_;
  std::mutex mu_;
  std::condition_variable cv_;
  bool gate_open_ = true;
  bool cancelled_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace tocd::acquisition::testing
