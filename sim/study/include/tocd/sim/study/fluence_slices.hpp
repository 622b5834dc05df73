#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mesh/tet_mesh.hpp"
#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::sim::study {

/// Finds the tet containing a point: tets are bucketed by their bounding boxes on a regular
/// grid (cells about twice the mean tet size), a query tests the tets of one cell with
/// barycentric coordinates. Points on a shared face go to either tet.
class TetLocator {
 public:
  explicit TetLocator(const mesh::TetMesh& mesh);
  /// Index of a tet containing `p`, or -1 outside the mesh.
  std::int32_t find(const mesh::Point3& p) const;

 private:
  const mesh::TetMesh* mesh_;
  mesh::Point3 lo_{}, cell_{};
  int n_[3]{1, 1, 1};
  std::vector<std::int32_t> start_;  ///< CSR: bucket b holds tets_[start_[b] .. start_[b+1])
  std::vector<std::int32_t> tets_;
  bool contains(std::int32_t t, const mesh::Point3& p) const;
};

/// A regular grid of points origin + i du + j dv, i < nu, j < nv.
struct SliceGrid {
  std::string name;  ///< "horizontal", "vertical"
  mesh::Point3 origin{};
  mesh::Point3 du{}, dv{};
  int nu = 0, nv = 0;
};

struct SliceSample {
  mesh::Point3 p{};
  std::int32_t tet = -1;  ///< -1: outside the mesh (fluence NaN)
  std::int32_t region = 0;
  double fluence = 0.0, fluence_se = 0.0;  ///< mm^-2 per launched weight
};

/// Samples the per-tet fluence of `result` (a run with tally_per_tet) on `grid`.
/// Throws tocd::Error when the result has no per-tet tallies for this mesh.
std::vector<SliceSample> sample_slice(const mesh::TetMesh& mesh, const TetLocator& locator,
                                      const mc::Result& result, const SliceGrid& grid);

/// CSV with header `x_mm,y_mm,z_mm,region,fluence,fluence_se`; points outside the mesh have
/// region 0 and empty fluence fields.
void write_slice_csv(const std::vector<SliceSample>& samples, const std::filesystem::path& path);

/// The two views of a pin-compression run: horizontal (z = tip_z, the whole box in x and y)
/// and vertical (the x-z plane through the pin axis y = 0, the whole box in x and z), with
/// points every `spacing_mm`.
std::vector<SliceGrid> standard_slices(const mesh::BoundingBox& box, double tip_z_mm,
                                       double spacing_mm = 0.05);

/// Files written for one run.
struct FluenceFiles {
  std::filesystem::path vtu, horizontal_csv, vertical_csv;
};

/// The names write_fluence_files gives the files of DIR and STEM.
FluenceFiles fluence_file_names(const std::filesystem::path& dir, const std::string& stem);

/// Writes DIR/STEM.vtu (per-tet fluence) and DIR/STEM_horizontal.csv, DIR/STEM_vertical.csv
/// (creating DIR). Throws tocd::Error when a file cannot be written.
FluenceFiles write_fluence_files(const mc::PreparedMesh& mesh, const mc::Result& result, double tip_z_mm,
                                 const std::filesystem::path& dir, const std::string& stem,
                                 double spacing_mm = 0.05, vtk::Format vtu_format = vtk::Format::binary);

}  // namespace tocd::sim::study
