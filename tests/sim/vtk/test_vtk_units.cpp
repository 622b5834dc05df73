// The .vtu writer's binary layout (read back here with zlib) and its checks; the .pvd series.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>
#include <zlib.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/vtk/pvd.hpp"
#include "tocd/sim/vtk/vtu.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/temp_dir.hpp"

namespace vtk = tocd::sim::vtk;

namespace {

using tocd::test::read_file;

// A line of `n` points, each consecutive pair a line cell (VTK_LINE = 3), with one value per point.
vtk::UnstructuredGrid line_grid(std::size_t n) {
  vtk::UnstructuredGrid g;
  std::vector<double> value;
  for (std::size_t i = 0; i < n; ++i) {
    g.points_xyz.insert(g.points_xyz.end(), {0.001 * static_cast<double>(i), 0.0, 0.0});
    value.push_back(1.0 / (1.0 + static_cast<double>(i)));
  }
  for (std::size_t i = 0; i + 1 < n; ++i)
    g.connectivity.insert(g.connectivity.end(),
                          {static_cast<std::int64_t>(i), static_cast<std::int64_t>(i + 1)});
  g.nodes_per_cell = 2;
  g.cell_type = 3;
  g.point_data.push_back({"value", 1, value});
  return g;
}

std::uint64_t word(const std::string& s, std::size_t at) {
  std::uint64_t v = 0;
  std::memcpy(&v, s.data() + at, sizeof v);
  return v;
}

}  // namespace

TEST(VtkFormat, ParsesItsTwoNamesAndRejectsOthers) {
  EXPECT_EQ(vtk::parse_format("binary"), vtk::Format::binary);
  EXPECT_EQ(vtk::parse_format("ascii"), vtk::Format::ascii);
  EXPECT_STREQ(vtk::to_string(vtk::Format::ascii), "ascii");
  EXPECT_THROW(vtk::parse_format("raw"), tocd::ConfigError);
}

TEST(VtuWriter, BinaryArraysAreZlibBlocksWithTheDocumentedHeader) {
  const std::size_t n = 5000;  // 40,000 bytes of Float64 values: one full 32 KiB block and a partial one
  const auto g = line_grid(n);
  const auto path = tocd::test::process_temp_path("line.vtu");
  vtk::write_vtu(g, path);
  const std::string text = read_file(path);
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(text.find("header_type=\"UInt64\""), std::string::npos);
  const std::string marker = "<AppendedData encoding=\"raw\">\n_";
  const std::size_t start = text.find(marker);
  ASSERT_NE(start, std::string::npos);
  const std::size_t data = start + marker.size();
  // The "value" array: find its offset attribute.
  const std::size_t decl = text.find("Name=\"value\"");
  ASSERT_NE(decl, std::string::npos);
  const std::size_t off_at = text.find("offset=\"", decl) + 8;
  const std::size_t offset = std::stoull(text.substr(off_at, text.find('"', off_at) - off_at));
  const std::size_t at = data + offset;
  ASSERT_EQ(word(text, at), 2U);                    // blocks
  EXPECT_EQ(word(text, at + 8), 32768U);            // uncompressed block size
  EXPECT_EQ(word(text, at + 16), 40000U - 32768U);  // partial last block
  std::vector<unsigned char> raw(40000);
  std::size_t in = at + 24 + 2 * 8, out = 0;
  for (int b = 0; b < 2; ++b) {
    const std::uint64_t compressed = word(text, at + 24 + 8 * b);
    uLongf len = raw.size() - out;
    ASSERT_EQ(
        uncompress(raw.data() + out, &len, reinterpret_cast<const Bytef*>(text.data() + in), compressed),
        Z_OK);
    in += compressed;
    out += len;
  }
  ASSERT_EQ(out, 40000U);
  const auto& values = std::get<std::vector<double>>(g.point_data[0].values);
  EXPECT_EQ(std::memcmp(raw.data(), values.data(), raw.size()), 0);  // every bit kept
  EXPECT_EQ(text.substr(text.size() - 28), "\n</AppendedData>\n</VTKFile>\n");
  std::filesystem::remove(path);
}

TEST(VtuWriter, AsciiIsPlainTextWithNineDigits) {
  const auto path = tocd::test::process_temp_path("line_ascii.vtu");
  vtk::write_vtu(line_grid(4), path, vtk::Format::ascii);
  const std::string text = read_file(path);
  EXPECT_EQ(text.find("AppendedData"), std::string::npos);
  EXPECT_EQ(text.find("compressor"), std::string::npos);
  EXPECT_NE(text.find("format=\"ascii\""), std::string::npos);
  EXPECT_NE(text.find("0.333333333 0.25"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(VtuWriter, SinglePrecisionWritesFloat32ThatTheAsciiDigitsRestoreExactly) {
  auto g = line_grid(4);
  g.single_precision = true;
  g.point_data.push_back({"id", 1, std::vector<std::int32_t>{7, 8, 9, 10}});
  const auto path = tocd::test::process_temp_path("line_single.vtu");
  vtk::write_vtu(g, path, vtk::Format::ascii);
  const std::string text = read_file(path);
  EXPECT_EQ(text.find("Float64"), std::string::npos);
  EXPECT_NE(text.find("<DataArray type=\"Float32\" NumberOfComponents=\"3\""), std::string::npos);
  EXPECT_NE(text.find("type=\"Int32\" Name=\"id\""), std::string::npos);  // integers keep their type
  // 1/3 as a float is 0.3333333432674408; 9 digits print it so that strtof gives it back.
  const std::size_t at = text.find("0.333333343");
  ASSERT_NE(at, std::string::npos);
  EXPECT_EQ(std::strtof(text.c_str() + at, nullptr), 1.0f / 3.0f);
  std::filesystem::remove(path);
}

TEST(VtuWriter, CellsAreOrderedByTheirLowestPointsAndTheirDataFollows) {
  vtk::UnstructuredGrid g;
  g.points_xyz = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
  g.connectivity = {3, 2, 0, 1, 2, 1};  // lines (3,2), (0,1), (2,1): written (0,1), (2,1), (3,2)
  g.nodes_per_cell = 2;
  g.cell_type = 3;
  g.cell_data.push_back({"tag", 1, std::vector<std::int32_t>{30, 10, 20}});
  const auto path = tocd::test::process_temp_path("order.vtu");
  vtk::write_vtu(g, path, vtk::Format::ascii);
  const std::string text = read_file(path);
  EXPECT_NE(text.find("Name=\"connectivity\" format=\"ascii\">\n0 1 2 1 3 2"), std::string::npos) << text;
  EXPECT_NE(text.find("Name=\"tag\" NumberOfComponents=\"1\" format=\"ascii\">\n10 20 30"), std::string::npos)
      << text;
  std::filesystem::remove(path);
}

TEST(VtuWriter, RejectsArraysThatDoNotMatchThePointsOrCells) {
  const auto path = tocd::test::process_temp_path("bad.vtu");
  auto g = line_grid(4);
  g.point_data[0].components = 2;
  EXPECT_THROW(vtk::write_vtu(g, path), tocd::Error);
  g = line_grid(4);
  g.connectivity.back() = 4;  // one past the last point
  EXPECT_THROW(vtk::write_vtu(g, path), tocd::Error);
  g = line_grid(4);
  g.connectivity.pop_back();
  EXPECT_THROW(vtk::write_vtu(g, path), tocd::Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(PvdWriter, ListsFilesBesideItRelativelyWithTheirTimesteps) {
  const auto dir = tocd::test::process_temp_path("series");
  std::filesystem::create_directories(dir);
  vtk::write_pvd({{0, dir / "sim00.vtu"}, {3, dir / "a&b.vtu"}, {7, "/elsewhere/x.vtu"}},
                 dir / "fluence.pvd");
  const std::string text = read_file(dir / "fluence.pvd");
  EXPECT_NE(text.find("type=\"Collection\""), std::string::npos);
  EXPECT_NE(text.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"sim00.vtu\"/>"),
            std::string::npos);
  EXPECT_NE(text.find("<DataSet timestep=\"3\" group=\"\" part=\"0\" file=\"a&amp;b.vtu\"/>"),
            std::string::npos);
  EXPECT_NE(text.find("file=\"/elsewhere/x.vtu\""), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "fluence.pvd.part"));
  std::filesystem::remove_all(dir);
}
