#include "decimator.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace tocd::gui {

MinMaxDecimator::MinMaxDecimator(double bucket_width, std::size_t max_buckets)
    : bucket_width_(bucket_width), max_buckets_(max_buckets) {
  if (!(bucket_width > 0.0) || !std::isfinite(bucket_width)) {
    throw std::invalid_argument("MinMaxDecimator: bucket width must be a positive number");
  }
  if (max_buckets == 0) {
    throw std::invalid_argument("MinMaxDecimator: at least one bucket must be kept");
  }
}

void MinMaxDecimator::add(double key, QPointF point) {
  const auto index = static_cast<long long>(std::floor(key / bucket_width_));
  const std::size_t seq = samples_seen_++;
  // A key that goes backwards (it should not) joins the newest bucket rather than
  // reordering history.
  if (buckets_.empty() || index > buckets_.back().index) {
    Bucket b;
    b.index = index;
    b.first = b.min = b.max = b.last = point;
    b.first_seq = b.min_seq = b.max_seq = b.last_seq = seq;
    buckets_.push_back(b);
    while (buckets_.size() > max_buckets_) buckets_.pop_front();
    return;
  }
  Bucket& b = buckets_.back();
  if (point.y() < b.min.y()) {
    b.min = point;
    b.min_seq = seq;
  }
  if (point.y() > b.max.y()) {
    b.max = point;
    b.max_seq = seq;
  }
  b.last = point;
  b.last_seq = seq;
}

void MinMaxDecimator::append_bucket_points(const Bucket& b, std::vector<QPointF>& out) const {
  // Emit the (up to) four kept samples in the order they arrived, without duplicates, so a
  // line through them follows the signal's shape.
  std::array<std::pair<std::size_t, QPointF>, 4> kept{
      {{b.first_seq, b.first}, {b.min_seq, b.min}, {b.max_seq, b.max}, {b.last_seq, b.last}}};
  std::sort(kept.begin(), kept.end(), [](const auto& a, const auto& c) { return a.first < c.first; });
  std::size_t previous = static_cast<std::size_t>(-1);
  for (const auto& [seq, p] : kept) {
    if (seq == previous) continue;
    out.push_back(p);
    previous = seq;
  }
}

std::vector<QPointF> MinMaxDecimator::points() const {
  std::vector<QPointF> out;
  out.reserve(buckets_.size() * 4);
  for (const Bucket& b : buckets_) append_bucket_points(b, out);
  return out;
}

void MinMaxDecimator::clear() {
  buckets_.clear();
  samples_seen_ = 0;
}

}  // namespace tocd::gui
