#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace tocd {

/// Mean and sample standard deviation in one pass (Welford), stable for long windows: the
/// engine's recording windows and the analyses of recorded samples.
class RunningStats {
 public:
  void add(double x) noexcept {
    ++n_;
    const double d = x - mean_;
    mean_ += d / static_cast<double>(n_);
    m2_ += d * (x - mean_);
  }
  std::int64_t n() const noexcept { return n_; }
  double mean() const noexcept { return n_ > 0 ? mean_ : std::numeric_limits<double>::quiet_NaN(); }
  double std() const noexcept {
    return n_ > 1 ? std::sqrt(m2_ / static_cast<double>(n_ - 1)) : std::numeric_limits<double>::quiet_NaN();
  }
  void reset() noexcept { *this = RunningStats{}; }

 private:
  std::int64_t n_ = 0;
  double mean_ = 0, m2_ = 0;
};

}  // namespace tocd
