#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/fe/result.hpp"
#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::sim::fe {

/// Quasi-static, displacement-controlled pin compression. Displacements (mm, pin travel from
/// first touch) must be positive, ascending and below the thickness; one FeStepResult per
/// requested value. Throws FeError on bad input; a solve that cannot go on (no convergence
/// at the smallest increment, an element about to invert) returns complete = false with the
/// steps reached and a stop_reason saying where and why it stopped.
FeResult solve(const FeModel& model, const std::vector<double>& displacements_mm);
/// The same, calling `on_increment` with the pin displacement (mm) after every converged load
/// increment, so that a caller can show how far the solve has come.
FeResult solve(const FeModel& model, const std::vector<double>& displacements_mm,
               const std::function<void(double)>& on_increment);

/// A pin compression solved a stretch at a time, as a run's steps come one after another: each
/// advance() goes on from the state the previous one reached, with the increments, step size
/// and predictor that one solve() over all the displacements so far would use, so its steps
/// are the same bits as that solve's. A run's steps are one loading path: the FE of a step
/// then costs the way from the previous step, not from first touch (docs/fe.md).
class PinCompression {
 public:
  /// Throws FeError when the model is invalid.
  explicit PinCompression(FeModel model);
  ~PinCompression();
  PinCompression(PinCompression&&) noexcept;
  PinCompression& operator=(PinCompression&&) noexcept;

  /// Solves on through `displacements_mm` (positive, ascending, above every displacement
  /// reached so far, below the thickness; FeError otherwise), as solve() does: one
  /// FeStepResult per displacement reached, `complete` false with a stop_reason when the solve
  /// cannot go on; after such a stop every later advance throws FeError. `on_increment` as
  /// in solve(); an exception it throws (a cancelled prediction) leaves the compression
  /// unusable too. The result's counts and seconds are this advance's.
  FeResult advance(const std::vector<double>& displacements_mm,
                   const std::function<void(double)>& on_increment = {});

  /// The displacements reached so far, in order (the path a later advance continues).
  const std::vector<double>& path_mm() const;
  /// False once a solve stopped or was interrupted: the state is then not on the path.
  bool usable() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// JSON summary (docs/fe.md): model, per-step force, areas, iterations, outlines.
nlohmann::json to_json(const FeResult& result, bool with_geometry = true);

/// VTK XML unstructured grid of one step (zlib-compressed binary by default, ASCII on
/// request), written atomically: the quads at their reference (undeformed) coordinates, the
/// point displacement (Warp By Vector at scale 1 gives the deformed shape), and per cell
/// min_log_strain, J and the compressed flag. Throws tocd::Error when it cannot be written.
void write_vtu(const FeStepResult& step, const std::filesystem::path& path,
               vtk::Format format = vtk::Format::binary);

}  // namespace tocd::sim::fe
