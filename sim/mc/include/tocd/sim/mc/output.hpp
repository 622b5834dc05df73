#pragma once

#include <filesystem>

#include <nlohmann/json.hpp>

#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::sim::mc {

/// The run summary as JSON (fields documented in docs/mc.md): photons, seed, threads,
/// transmittance / reflectance / side_loss / absorbed / specular ... each as
/// {"mean", "se"}, exit_by_marker, absorbed_by_region, events, seconds, photons_per_second.
nlohmann::json to_json(const Result& result);

/// Writes a VTK XML UnstructuredGrid (.vtu; zlib-compressed binary by default, ASCII on
/// request) with the tets and, per cell, fluence (mm^-2 per launched weight), its standard
/// error, the absorbed weight and the region. ParaView opens it directly. Written
/// atomically. Throws tocd::Error when the file cannot be written or the result holds no
/// per-tet tallies.
void write_fluence_vtu(const PreparedMesh& mesh, const Result& result, const std::filesystem::path& path,
                       vtk::Format format = vtk::Format::binary);

}  // namespace tocd::sim::mc
