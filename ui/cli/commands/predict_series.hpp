#pragma once

// `tocdlab predict --db FILE --run ID --output-dir DIR`: a run's stored predictions re-run
// with their fluence written, one .vtu per step and a ParaView series run.pvd.

#include <cstdint>
#include <string>

#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::cli {

struct RunSeriesOptions {
  std::string db, output_dir;
  std::int64_t run = 0;
  int threads = 0;
  sim::vtk::Format format = sim::vtk::Format::binary;
  bool json = false;
};

/// Re-runs the latest stored prediction config of each step of the run (its step part: the
/// fluence shown is the step's, not the glass-only baseline's) with the fluence written to
/// `output_dir` as step001.vtu, step002.vtu, ... and writes output_dir/run.pvd listing them
/// with the step number as the time. Throws tocd::Error (unknown run, a run without stored
/// predictions, a stored config that does not parse).
void predict_run_series(const RunSeriesOptions& options);

}  // namespace tocd::cli
