#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

#include "input_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/plot/inputs.hpp"

namespace tocd::plot {
namespace {

struct Point {
  std::array<double, 3> xyz{};
  int region = 0;
  double fluence = std::numeric_limits<double>::quiet_NaN();
};

[[noreturn]] void fail(const std::string& source, int line, const std::string& what) {
  throw ConfigError(source + ":" + std::to_string(line) + ": " + what);
}

double parse_number(std::string_view s, const std::string& source, int line, const char* column) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v))
    fail(source, line, std::string(column) + " '" + std::string(s) + "' is not a number");
  return v;
}

// Shortest text that reads back as `v` to 6 digits (as the CSV writes its coordinates).
std::string number_text(double v) {
  std::ostringstream out;
  out.precision(6);
  out << (std::abs(v) < 1e-9 ? 0.0 : v);
  return out.str();
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  for (;;) {
    const auto comma = line.find(',', start);
    out.push_back(line.substr(start, comma - start));
    if (comma == std::string_view::npos) return out;
    start = comma + 1;
  }
}

// The distinct values of one coordinate. Grid points are written with 9 significant digits,
// so values closer than 1e-6 mm are the same grid line.
std::vector<double> distinct(const std::vector<Point>& pts, int axis) {
  std::set<double> s;
  for (const auto& p : pts) s.insert(std::round(p.xyz[axis] * 1e6) / 1e6);
  return {s.begin(), s.end()};
}

}  // namespace

Slice parse_slice_csv(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  int n = 0;
  if (!std::getline(in, line)) fail(source, 1, "the file is empty (expected a fluence slice CSV)");
  ++n;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line.rfind("x_mm,y_mm,z_mm,region,fluence", 0) != 0)
    fail(source, 1,
         "header '" + line + "' is not a fluence slice's (x_mm,y_mm,z_mm,region,fluence,fluence_se)");
  std::vector<Point> pts;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const auto f = split(line);
    if (f.size() < 5) fail(source, n, "expected 6 fields, found " + std::to_string(f.size()));
    Point p;
    p.xyz = {parse_number(f[0], source, n, "x_mm"), parse_number(f[1], source, n, "y_mm"),
             parse_number(f[2], source, n, "z_mm")};
    p.region = static_cast<int>(parse_number(f[3], source, n, "region"));
    if (!f[4].empty()) p.fluence = parse_number(f[4], source, n, "fluence");
    pts.push_back(p);
  }
  if (pts.empty()) fail(source, n, "no grid points after the header");
  std::vector<int> axes;
  std::array<std::vector<double>, 3> values;
  for (int a = 0; a < 3; ++a) {
    values[a] = distinct(pts, a);
    if (values[a].size() > 1) axes.push_back(a);
  }
  if (axes.size() != 2)
    fail(source, n, std::to_string(axes.size()) + " coordinates vary; a slice has exactly two");
  const auto& u = values[axes[0]];
  const auto& v = values[axes[1]];
  Slice s;
  static constexpr std::array<const char*, 3> kNames{"x (mm)", "y (mm)", "z (mm)"};
  // The plane: the coordinate that does not vary, as "z = 1 mm".
  const int fixed = 3 - axes[0] - axes[1];
  s.title = std::string(1, "xyz"[fixed]) + " = " + number_text(values[fixed].front()) + " mm";
  s.x_label = kNames[axes[0]];
  s.y_label = kNames[axes[1]];
  s.nx = static_cast<int>(u.size());
  s.ny = static_cast<int>(v.size());
  if (static_cast<std::size_t>(s.nx) * s.ny != pts.size())
    fail(source, n,
         std::to_string(pts.size()) + " points do not fill a " + std::to_string(s.nx) + " x " +
             std::to_string(s.ny) + " grid");
  // Each point is the centre of its cell: the picture covers half a spacing beyond the ends.
  const double hu = (u.back() - u.front()) / (s.nx - 1), hv = (v.back() - v.front()) / (s.ny - 1);
  s.x_min = u.front() - hu / 2, s.x_max = u.back() + hu / 2;
  s.y_min = v.front() - hv / 2, s.y_max = v.back() + hv / 2;
  s.fluence.assign(pts.size(), std::numeric_limits<double>::quiet_NaN());
  s.region.assign(pts.size(), 0);
  for (const auto& p : pts) {
    const auto i = static_cast<std::size_t>(std::lround((p.xyz[axes[0]] - u.front()) / hu));
    const auto j = static_cast<std::size_t>(std::lround((p.xyz[axes[1]] - v.front()) / hv));
    s.fluence[j * s.nx + i] = p.fluence;
    s.region[j * s.nx + i] = p.region;
  }
  return s;
}

Slice read_slice_csv(const std::filesystem::path& path) {
  Slice s = parse_slice_csv(detail::read_input_file(path, "slice file"), path.string());
  s.title = path.stem().string() + " (" + s.title + ")";
  return s;
}

}  // namespace tocd::plot
