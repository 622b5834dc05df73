// The tester's reading: samples, the load window, and the load interlock, which stops the pin
// from the poller itself (it owns the driver, so no queue stands in between).
#include "tester_channel.hpp"

#include <fmt/format.h>

#include "capability_check.hpp"

namespace tocd::acquisition {

namespace {
// The order require_channels() checks the driver's table for.
constexpr std::size_t kDisplacementChannel = 0, kLoadChannel = 1;
}  // namespace

TesterChannel::TesterChannel(std::unique_ptr<devices::MechanicalTester> driver)
    : InstrumentChannel(driver->describe()), driver_(std::move(driver)) {
  require_channels(capabilities(), {"displacement", "load"});
}

void TesterChannel::set_run(double contact_position_mm, double max_load_N, double settle_keep_s) {
  contact_mm_ = contact_position_mm;
  max_load_N_ = max_load_N;
  load_window_.set_keep(settle_keep_s);
}

TesterSnapshot TesterChannel::latest() const {
  std::lock_guard lock(mu_);
  return latest_;
}

std::uint64_t TesterChannel::send_stop() {
  return commands_.push("stop", [this] { driver_->stop(); });
}

std::uint64_t TesterChannel::send_move(std::string what, double position_mm, double speed_mm_per_s) {
  return commands_.push(std::move(what), [this, position_mm, speed_mm_per_s] {
    driver_->move_to(position_mm, speed_mm_per_s);
  });
}

void TesterChannel::send_clear_fault(std::string why) {
  commands_.push(std::move(why), [this] { driver_->clear_fault(); });
}

void TesterChannel::read(PollerContext& ctx, std::uint64_t commands_run, std::vector<LiveSample>& live) {
  const devices::TesterReading r = driver_->read();
  const std::int64_t t = ctx.clock.now_ns();
  const double d = r.position_mm - contact_mm_;
  {
    std::lock_guard lock(mu_);
    latest_ = {d, r.load_N, r.status.moving, r.status.at_target, r.status.limit, commands_run};
  }
  record(ctx, kDisplacementChannel, t, d, live);
  record(ctx, kLoadChannel, t, r.load_N, live);
  load_window_.add(t, r.load_N);
  const auto armed = interlock_.armed();
  if (!armed || armed->arming == tripped_arming_) return;
  std::string why = interlock_reason(r, d);
  if (why.empty()) return;
  tripped_arming_ = armed->arming;
  // Stop first, then say why.
  try {
    driver_->stop();
  } catch (const std::exception& e) {
    why += fmt::format("; stop command failed: {}", e.what());
  }
  ctx.faults.trip(why);
}

std::string TesterChannel::interlock_reason(const devices::TesterReading& r, double d) {
  if (r.load_N > max_load_N_) {
    return fmt::format("load {:.3f} N above the {:.3f} N limit at displacement {:.4f} mm", r.load_N,
                       max_load_N_, d);
  }
  if ((r.status.limit || r.status.fault) && !limit_reported_) {
    limit_reported_ = true;
    return fmt::format("mechanical tester reports {} (fault code {}) at displacement {:.4f} mm",
                       r.status.limit ? "a limit" : "a fault", r.status.fault_code, d);
  }
  return "";
}

void TesterChannel::lost() {
  InstrumentChannel::lost();  // no more commands reach it: the sequencer stops waiting on them
  try {
    driver_->stop();
  } catch (const std::exception&) {  // the link is gone; nothing more to do
  }
}

}  // namespace tocd::acquisition
