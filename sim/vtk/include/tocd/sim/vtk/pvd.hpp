#pragma once

#include <filesystem>
#include <vector>

namespace tocd::sim::vtk {

/// One dataset of a ParaView collection: its file and the time it is shown at.
struct PvdEntry {
  double timestep = 0;
  std::filesystem::path file;
};

/// Writes a .pvd collection (ParaView's series file) atomically. Files inside the .pvd's own
/// folder are referenced relative to it, so the folder can be moved as a whole. Throws
/// tocd::Error when the file cannot be written.
void write_pvd(const std::vector<PvdEntry>& entries, const std::filesystem::path& path);

}  // namespace tocd::sim::vtk
