#pragma once

#include <filesystem>
#include <functional>
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

/// JSON summary (docs/fe.md): model, per-step force, areas, iterations, outlines.
nlohmann::json to_json(const FeResult& result, bool with_geometry = true);

/// VTK XML unstructured grid of one step (zlib-compressed binary by default, ASCII on
/// request), written atomically: the quads at their reference (undeformed) coordinates, the
/// point displacement (Warp By Vector at scale 1 gives the deformed shape), and per cell
/// min_log_strain, J and the compressed flag. Throws tocd::Error when it cannot be written.
void write_vtu(const FeStepResult& step, const std::filesystem::path& path,
               vtk::Format format = vtk::Format::binary);

}  // namespace tocd::sim::fe
