#pragma once
// A StudyTable filled row by row, the same way by the one-process and the distributed study.

#include <chrono>
#include <functional>

#include "tocd/sim/study/study.hpp"

namespace tocd::sim::study {

class TableBuilder {
 public:
  TableBuilder(const StudySettings& settings, int ref_a, int ref_b);
  /// The row of case `c` before it runs: its request with the fluence file stem, its strain.
  static StudyRow start_row(const StudyCase& c);
  /// Appends a finished row, recomputes the relative columns and reports the row.
  void add(StudyRow row, const std::function<void(const StudyRow&)>& progress);
  /// The table with its wall time and its fluence series (.pvd) written.
  StudyTable finish();

 private:
  StudyTable table_;
  std::chrono::steady_clock::time_point t0_ = std::chrono::steady_clock::now();
};

}  // namespace tocd::sim::study
