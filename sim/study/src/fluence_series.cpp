// The ParaView series (.pvd) of a study's per-simulation fluence files.
#include <vector>

#include "tocd/sim/study/study.hpp"
#include "tocd/sim/vtk/pvd.hpp"

namespace tocd::sim::study {

std::string write_fluence_series(const StudyTable& table) {
  std::vector<vtk::PvdEntry> entries;
  for (const auto& row : table.rows)
    if (row.p.fluence.contains("vtu"))
      entries.push_back({static_cast<double>(row.c.id), row.p.fluence["vtu"].get<std::string>()});
  if (entries.empty()) return {};
  // Beside the fluence files (the study writes them all to one folder).
  const std::filesystem::path path = entries.front().file.parent_path() / "fluence.pvd";
  vtk::write_pvd(entries, path);
  return path.string();
}

}  // namespace tocd::sim::study
