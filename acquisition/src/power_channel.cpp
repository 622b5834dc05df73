#include "power_channel.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "capability_check.hpp"

namespace tocd::acquisition {

namespace {

/// A power reading below -this x baseline is not zero noise but a broken reading.
constexpr double kNegativePowerTolerance = 0.01;
constexpr std::size_t kPowerChannel = 0;

}  // namespace

PowerChannel::PowerChannel(std::unique_ptr<devices::PowerMeter> driver)
    : InstrumentChannel(driver->describe()), driver_(std::move(driver)) {
  require_channels(capabilities(), {"power"});
}

void PowerChannel::set_run(double baseline_W, bool over_range_pauses) {
  baseline_W_ = baseline_W;
  over_range_pauses_ = over_range_pauses;
}

double PowerChannel::latest_W() const {
  std::lock_guard lock(mu_);
  return latest_W_;
}

void PowerChannel::read(PollerContext& ctx, std::uint64_t, std::vector<LiveSample>& live) {
  const devices::PowerReading r = driver_->measure();
  const std::int64_t t = ctx.clock.now_ns();
  // Over range first: no sample and no broken read, but a window it falls into is no
  // measurement.
  if (r.over_range) {
    ctx.faults.count();
    if (over_range_reported_) return;
    over_range_reported_ = true;
    const std::string why = fmt::format("power meter over range ({:.4g} W)", r.power_W);
    if (over_range_pauses_) {
      ctx.faults.pause(why);
    } else {
      ctx.events.emit("fault", why);
    }
    return;
  }
  over_range_reported_ = false;
  // A reading that cannot be light on the sensor is a failed read, not a sample.
  if (!std::isfinite(r.power_W))
    throw std::runtime_error(fmt::format("reading {} W is not a number", r.power_W));
  if (r.power_W < -kNegativePowerTolerance * baseline_W_) {
    throw std::runtime_error(fmt::format(
        "reading {:.4g} W is negative beyond the sensor's zero noise (more than {} % of the baseline)",
        r.power_W, kNegativePowerTolerance * 100.0));
  }
  {
    std::lock_guard lock(mu_);
    latest_W_ = r.power_W;
  }
  record(ctx, kPowerChannel, t, r.power_W, live);
}

}  // namespace tocd::acquisition
