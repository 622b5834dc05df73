#pragma once

#include <QPointF>
#include <cstddef>
#include <deque>
#include <vector>

namespace tocd::gui {

/// Display decimation for fast streams (1 kHz load/displacement): samples are grouped into
/// buckets of `bucket_width` along a monotonic key (time), and each closed bucket keeps only
/// its first, minimum, maximum and last point in arrival order. A chart then draws at most
/// four points per bucket, yet every spike still reaches the screen, which plain
/// subsampling would lose. Display only: the database always gets every sample.
///
/// Not thread-safe; the owner (a chart on the GUI thread) feeds it from buffered batches.
class MinMaxDecimator {
 public:
  /// `bucket_width` > 0 in key units (s for time charts); `max_buckets` bounds memory: the
  /// oldest buckets are dropped first (a rolling window of max_buckets * bucket_width).
  explicit MinMaxDecimator(double bucket_width, std::size_t max_buckets = 2000);

  /// Adds one sample: `key` orders buckets (must not decrease), `point` is what is drawn
  /// (x may differ from the key, e.g. displacement on a load-vs-displacement chart).
  void add(double key, QPointF point);

  /// The decimated points, oldest first, including the still-open bucket.
  std::vector<QPointF> points() const;

  void clear();
  std::size_t samples_seen() const noexcept { return samples_seen_; }
  std::size_t bucket_count() const noexcept { return buckets_.size(); }
  double bucket_width() const noexcept { return bucket_width_; }

 private:
  struct Bucket {
    long long index = 0;  ///< floor(key / bucket_width)
    QPointF first, min, max, last;
    std::size_t first_seq = 0, min_seq = 0, max_seq = 0, last_seq = 0;
  };
  void append_bucket_points(const Bucket& b, std::vector<QPointF>& out) const;

  double bucket_width_;
  std::size_t max_buckets_;
  std::deque<Bucket> buckets_;
  std::size_t samples_seen_ = 0;
};

}  // namespace tocd::gui
