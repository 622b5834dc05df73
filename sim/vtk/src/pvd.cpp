#include "tocd/sim/vtk/pvd.hpp"

#include <ostream>
#include <string>

#include <fmt/format.h>

#include "tocd/core/atomic_file.hpp"

namespace tocd::sim::vtk {
namespace {

std::string xml_escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

void write_pvd(const std::vector<PvdEntry>& entries, const std::filesystem::path& path) {
  const std::filesystem::path dir = path.parent_path();
  tocd::AtomicFile file(path);
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" "
         "byte_order=\"LittleEndian\">\n"
         "<Collection>\n";
  for (const auto& e : entries) {
    // Relative to the .pvd when the file lies beside it or below it; absolute otherwise.
    std::filesystem::path ref = e.file;
    if (e.file.parent_path() == dir || (dir.empty() && e.file.is_relative()))
      ref = e.file.filename();
    else if (ref.is_relative())
      ref = std::filesystem::absolute(ref);
    out << fmt::format("<DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", e.timestep,
                       xml_escaped(ref.string()));
  }
  out << "</Collection>\n</VTKFile>\n";
  file.commit();
}

}  // namespace tocd::sim::vtk
