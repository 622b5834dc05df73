// Pin-compression and vacuum steps (step_strategy.hpp).
#include <cmath>

#include <fmt/format.h>

#include "engine_impl.hpp"
#include "step_strategy.hpp"

namespace tocd::acquisition {

namespace {

class PinSteps final : public StepStrategy {
 public:
  explicit PinSteps(Engine::Impl& m) : m_(m) {}
  std::string target_text(const ProtocolStep& step) const override {
    return fmt::format("pin to {} mm", step.displacement_mm);
  }
  Interrupt approach(const ProtocolStep& step) override {
    const double target = m_.protocol.contact_position_mm + step.displacement_mm;
    Interrupt why = Interrupt::none;
    std::string problem;
    const MoveResult moved =
        m_.move_and_wait(target, m_.protocol.approach_speed_mm_per_s, true, why, problem);
    if (moved == MoveResult::interrupted) return why;
    if (moved != MoveResult::arrived) return m_.move_failed(step, problem);
    return Interrupt::none;
  }
  RateWindow& settle_window() override { return m_.load_window; }
  const char* settle_unit() const override { return "N"; }
  void set_targets(const ProtocolStep& step, db::StepRecord& rec) const override {
    rec.target_displacement_mm = step.displacement_mm;
    rec.nominal_strain = step.nominal_strain;
  }
  std::optional<double> target_displacement_mm(const ProtocolStep& step) const override {
    return step.displacement_mm;
  }
  void recorded(const StepResult& r) override {
    // The model is asked about the displacement the window measured, not the one it aimed at.
    m_.predictions.push({m_.run_id, r.index, r.measured_displacement_mm, m_.protocol.sample.thickness_mm,
                         r.load_N, r.measured_T});
  }

 private:
  Engine::Impl& m_;
};

class VacuumSteps final : public StepStrategy {
 public:
  explicit VacuumSteps(Engine::Impl& m) : m_(m) {}
  std::string target_text(const ProtocolStep& step) const override {
    return fmt::format("vacuum to {} kPa", step.pressure_kPa);
  }
  Interrupt approach(const ProtocolStep& step) override {
    m_.seal_watch = false;
    const double p = step.pressure_kPa;
    m_.send_vacuum(fmt::format("vacuum to {} kPa", p), [this, p] {
      m_.inst.vacuum->set_vent(false);
      m_.inst.vacuum->set_setpoint_kPa(p);
      m_.inst.vacuum->run_pump(true);
    });
    bool reached = false;
    const Interrupt why = m_.wait_until(m_.protocol.settle.max_wait_s + m_.opt.move_timeout_margin_s, [&] {
      reached = std::abs(m_.latest[kPressure] - p) <= m_.opt.vacuum_reached_kPa;
      return reached;
    });
    if (why != Interrupt::none) return why;
    if (!reached) {
      m_.trip(fmt::format("vacuum did not reach {} kPa (last {:.2f} kPa)", p, m_.latest[kPressure].load()));
      return Interrupt::trip;
    }
    m_.seal_setpoint_kPa = p;
    m_.seal_watch = true;
    return Interrupt::none;
  }
  RateWindow& settle_window() override { return m_.pressure_window; }
  const char* settle_unit() const override { return "kPa"; }
  void set_targets(const ProtocolStep& step, db::StepRecord& rec) const override {
    rec.target_pressure_kPa = step.pressure_kPa;
  }
  std::optional<double> target_displacement_mm(const ProtocolStep&) const override { return std::nullopt; }
  void recorded(const StepResult&) override {}  // the simulator models pin compression only

 private:
  Engine::Impl& m_;
};

}  // namespace

std::unique_ptr<StepStrategy> make_pin_steps(Engine::Impl& engine) {
  return std::make_unique<PinSteps>(engine);
}
std::unique_ptr<StepStrategy> make_vacuum_steps(Engine::Impl& engine) {
  return std::make_unique<VacuumSteps>(engine);
}

}  // namespace tocd::acquisition
