#pragma once

#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>

namespace tocd::acquisition {

/// The recent history of one channel, for the settle criterion: least-squares slope (units
/// per second) of the readings in the last `window_s`. Thread-safe (one poller adds, the
/// sequencer asks).
class RateWindow {
 public:
  explicit RateWindow(double keep_s = 2.0) : keep_ns_(static_cast<std::int64_t>(keep_s * 1e9)) {}

  void set_keep(double keep_s) {
    std::lock_guard lock(mu_);
    keep_ns_ = static_cast<std::int64_t>(keep_s * 1e9);
  }

  void add(std::int64_t t_ns, double value) {
    std::lock_guard lock(mu_);
    points_.push_back({t_ns, value});
    while (!points_.empty() && points_.front().t_ns < t_ns - keep_ns_) points_.pop_front();
  }

  /// Slope over the readings taken in [now - window, now], none of them before `not_before_ns`;
  /// empty while those readings do not yet span 90 % of the window (or are fewer than 3).
  std::optional<double> slope_per_s(std::int64_t now_ns, double window_s, std::int64_t not_before_ns) const {
    const auto window_ns = static_cast<std::int64_t>(window_s * 1e9);
    const std::int64_t from = std::max(now_ns - window_ns, not_before_ns);
    std::lock_guard lock(mu_);
    double n = 0, st = 0, sv = 0, stt = 0, stv = 0;
    std::int64_t first = 0, last = 0;
    for (const auto& p : points_) {
      if (p.t_ns < from) continue;
      if (n == 0) first = p.t_ns;
      last = p.t_ns;
      const double t = static_cast<double>(p.t_ns - from) * 1e-9;
      n += 1;
      st += t;
      sv += p.value;
      stt += t * t;
      stv += t * p.value;
    }
    if (n < 3 || static_cast<double>(last - first) < 0.9 * static_cast<double>(window_ns))
      return std::nullopt;
    const double den = n * stt - st * st;
    if (!(den > 0)) return std::nullopt;
    return (n * stv - st * sv) / den;
  }

 private:
  struct Point {
    std::int64_t t_ns;
    double value;
  };
  mutable std::mutex mu_;
  std::deque<Point> points_;
  std::int64_t keep_ns_;
};

}  // namespace tocd::acquisition
