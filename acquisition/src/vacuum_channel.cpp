#include "vacuum_channel.hpp"

#include <fmt/format.h>

#include "capability_check.hpp"

namespace tocd::acquisition {

namespace {
constexpr std::size_t kPressureChannel = 0;
}

VacuumChannel::VacuumChannel(std::unique_ptr<devices::VacuumController> driver)
    : InstrumentChannel(driver->describe()), driver_(std::move(driver)) {
  require_channels(capabilities(), {"pressure"});
}

void VacuumChannel::set_run(double vacuum_loss_kPa, double settle_keep_s) {
  loss_kPa_ = vacuum_loss_kPa;
  pressure_window_.set_keep(settle_keep_s);
}

double VacuumChannel::latest_kPa() const {
  std::lock_guard lock(mu_);
  return latest_kPa_;
}

void VacuumChannel::send_setpoint(double p) {
  commands_.push(fmt::format("vacuum to {} kPa", p), [this, p] {
    driver_->set_vent(false);
    driver_->set_setpoint_kPa(p);
    driver_->run_pump(true);
  });
}

void VacuumChannel::send_vent() {
  commands_.push("pump off, vent", [this] {
    driver_->run_pump(false);
    driver_->set_vent(true);
  });
}

void VacuumChannel::read(PollerContext& ctx, std::uint64_t, std::vector<LiveSample>& live) {
  const devices::VacuumReading r = driver_->read();
  const std::int64_t t = ctx.clock.now_ns();
  {
    std::lock_guard lock(mu_);
    latest_kPa_ = r.pressure_kPa;
  }
  record(ctx, kPressureChannel, t, r.pressure_kPa, live);
  pressure_window_.add(t, r.pressure_kPa);
  const auto armed = seal_watch_.armed();
  if (armed && armed->arming != reported_arming_ && r.pressure_kPa > armed->setpoint + loss_kPa_) {
    reported_arming_ = armed->arming;
    ctx.faults.pause(fmt::format("vacuum seal loss: {:.2f} kPa, setpoint {:.2f} kPa (limit +{:.2f} kPa)",
                                 r.pressure_kPa, armed->setpoint, loss_kPa_));
  }
}

}  // namespace tocd::acquisition
