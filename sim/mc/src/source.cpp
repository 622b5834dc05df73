#include "tocd/sim/mc/source.hpp"

#include <cstdlib>
#include <vector>

#include <fmt/format.h>

namespace tocd::sim::mc {
namespace {

std::vector<double> numbers(const std::string& text, const std::string& whole) {
  std::vector<double> out;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    const std::size_t comma = std::min(text.find(',', pos), text.size());
    const std::string tok = text.substr(pos, comma - pos);
    char* end = nullptr;
    const double v = std::strtod(tok.c_str(), &end);
    if (tok.empty() || *end != '\0')
      throw SourceError(fmt::format("source '{}': '{}' is not a number", whole, tok));
    out.push_back(v);
    pos = comma + 1;
  }
  return out;
}

}  // namespace

Source parse_source(const std::string& text, const mesh::BoundingBox& box) {
  std::string spec = text;
  Source s;
  constexpr std::string_view kNoSpec = ",nospec";
  if (spec.size() > kNoSpec.size() && spec.ends_with(kNoSpec)) {
    s.entry_specular = false;
    spec.resize(spec.size() - kNoSpec.size());
  }
  const auto colon = spec.find(':');
  const std::string kind = spec.substr(0, colon);
  const std::vector<double> v =
      colon == std::string::npos ? std::vector<double>{} : numbers(spec.substr(colon + 1), text);
  const double cx = 0.5 * (box.min[0] + box.max[0]), cy = 0.5 * (box.min[1] + box.max[1]);
  // Beams given by (x, y) start one box-height above the top, pointing down.
  const double above = box.max[2] + (box.max[2] - box.min[2]) + 1.0;
  auto bad_count = [&](const char* forms) {
    return SourceError(fmt::format("source '{}': {} takes {}", text, kind, forms));
  };
  if (kind == "pencil") {
    s.kind = Source::Kind::pencil;
    if (v.empty())
      s.origin = {cx, cy, above};
    else if (v.size() == 2)
      s.origin = {v[0], v[1], above};
    else if (v.size() == 6) {
      s.origin = {v[0], v[1], v[2]};
      s.direction = {v[3], v[4], v[5]};
    } else
      throw bad_count("no numbers, X,Y or X,Y,Z,DX,DY,DZ");
  } else if (kind == "disk") {
    s.kind = Source::Kind::disk;
    if (v.size() == 1) {
      s.origin = {cx, cy, above};
      s.radius_mm = v[0];
    } else if (v.size() == 3) {
      s.origin = {v[0], v[1], above};
      s.radius_mm = v[2];
    } else if (v.size() == 7) {
      s.origin = {v[0], v[1], v[2]};
      s.direction = {v[3], v[4], v[5]};
      s.radius_mm = v[6];
    } else
      throw bad_count("R, X,Y,R or X,Y,Z,DX,DY,DZ,R");
    if (!(s.radius_mm > 0.0)) throw SourceError(fmt::format("source '{}': disk radius must be > 0", text));
  } else if (kind == "marker") {
    s.kind = Source::Kind::marker;
    if (v.size() != 1 || v[0] != static_cast<double>(static_cast<std::int32_t>(v[0])))
      throw bad_count("one integer N");
    s.marker = static_cast<std::int32_t>(v[0]);
  } else {
    throw SourceError(
        fmt::format("source '{}': unknown kind '{}' (expected pencil, disk or marker)", text, kind));
  }
  return s;
}

std::string describe(const Source& s) {
  const std::string spec = s.entry_specular ? "" : ", no entry specular";
  switch (s.kind) {
    case Source::Kind::pencil:
      return fmt::format("pencil beam through ({}, {}, {}) along ({}, {}, {}){}", s.origin[0], s.origin[1],
                         s.origin[2], s.direction[0], s.direction[1], s.direction[2], spec);
    case Source::Kind::disk:
      return fmt::format("collimated disk r = {} mm centred ({}, {}, {}) along ({}, {}, {}){}", s.radius_mm,
                         s.origin[0], s.origin[1], s.origin[2], s.direction[0], s.direction[1],
                         s.direction[2], spec);
    case Source::Kind::marker:
    default:
      return fmt::format("collimated over boundary faces with marker {}{}", s.marker, spec);
  }
}

}  // namespace tocd::sim::mc
