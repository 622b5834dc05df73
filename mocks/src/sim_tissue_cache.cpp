#include "tocd/mocks/sim_tissue_cache.hpp"

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "tocd/core/atomic_file.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/version.hpp"

namespace tocd::mocks {

namespace {

// Bumped whenever the file layout or the meaning of a field changes.
constexpr int kCacheFormat = 1;

std::uint64_t fnv1a64(const std::string& text) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

std::string env(const char* name) {
  const char* v = std::getenv(name);
  return v ? std::string(v) : std::string();
}

bool all_finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Why a table read from disk cannot be the one `spec` would build, or "" when it can.
std::string inconsistency(const SimTissueTable& t, const SimTissueSpec& spec) {
  const std::size_t n = spec.displacements_mm.size() + 1;  // contact (0 mm) first
  if (t.displacement_mm.size() != n || t.load_N.size() != n || t.transmission.size() != n ||
      t.transmission_stderr.size() != n)
    return fmt::format("tables have {} rows, expected {}", t.displacement_mm.size(), n);
  if (!all_finite(t.displacement_mm) || !all_finite(t.load_N) || !all_finite(t.transmission) ||
      !all_finite(t.transmission_stderr))
    return "a table holds a non-finite number";
  if (t.displacement_mm[0] != 0.0) return "first displacement is not 0";
  for (std::size_t k = 1; k < n; ++k)
    if (t.displacement_mm[k] != spec.displacements_mm[k - 1]) return "displacements differ from the key";
  for (std::size_t k = 0; k < n; ++k)
    if (t.transmission[k] < 0 || t.transmission_stderr[k] < 0) return "negative transmission";
  return "";
}

}  // namespace

std::filesystem::path default_sim_tissue_cache_dir() {
  if (const std::string dir = env("TOCDLAB_CACHE_DIR"); !dir.empty()) return dir;
  if (const std::string xdg = env("XDG_CACHE_HOME"); !xdg.empty())
    return std::filesystem::path(xdg) / "tocdlab";
  if (const std::string home = env("HOME"); !home.empty())
    return std::filesystem::path(home) / ".cache" / "tocdlab";
  return {};
}

std::string sim_tissue_cache_key(const SimTissueSpec& s) {
  // {:.17g} writes every double so that it reads back to the same bits.
  std::string key = fmt::format(
      "tocdlab simulated sample; format {}; tocdlab {}; thickness_mm {:.17g}; stiffness_scale {:.17g}; "
      "optics_model {}; photons {}; seed {}; displacements_mm",
      kCacheFormat, tocd::version(), s.thickness_mm, s.stiffness_scale, s.optics_model, s.photons, s.seed);
  for (double d : s.displacements_mm) key += fmt::format(" {:.17g}", d);
  // The clearing (since the truth became settable): written only when it differs from the
  // published one, so the keys of the default sample, and the entries cached before, stay valid.
  const SimTissueSpec published;
  if (s.cleared_mu_a_fraction != published.cleared_mu_a_fraction ||
      s.cleared_mu_s_fraction != published.cleared_mu_s_fraction ||
      s.cleared_n_fraction != published.cleared_n_fraction ||
      s.full_clearing_strain != published.full_clearing_strain)
    key += fmt::format(
        "; cleared_fractions mu_a {:.17g} mu_s {:.17g} n {:.17g}; full_clearing_strain {:.17g}",
        s.cleared_mu_a_fraction, s.cleared_mu_s_fraction, s.cleared_n_fraction, s.full_clearing_strain);
  return key;
}

std::filesystem::path sim_tissue_cache_file(const std::filesystem::path& dir, const SimTissueSpec& spec) {
  return dir / fmt::format("sim-sample-{:016x}.json", fnv1a64(sim_tissue_cache_key(spec)));
}

std::optional<SimTissueTable> load_sim_tissue_table(const std::filesystem::path& file,
                                                    const SimTissueSpec& spec, std::string& why) {
  std::ifstream in(file);
  if (!in) {
    why = "no cache entry";
    return std::nullopt;
  }
  try {
    const nlohmann::json j = nlohmann::json::parse(in);
    if (!j.is_object() || j.value("key", std::string()) != sim_tissue_cache_key(spec)) {
      why = "cache entry belongs to another configuration";
      return std::nullopt;
    }
    SimTissueTable t;
    t.displacement_mm = j.at("displacement_mm").get<std::vector<double>>();
    t.load_N = j.at("load_N").get<std::vector<double>>();
    t.transmission = j.at("transmission").get<std::vector<double>>();
    t.transmission_stderr = j.at("transmission_se").get<std::vector<double>>();
    t.seconds = j.at("seconds").get<double>();
    if (why = inconsistency(t, spec); !why.empty()) return std::nullopt;
    return t;
  } catch (const nlohmann::json::exception& e) {
    why = fmt::format("cache entry unreadable ({})", e.what());
    return std::nullopt;
  }
}

void store_sim_tissue_table(const std::filesystem::path& file, const SimTissueSpec& spec,
                            const SimTissueTable& t) {
  std::error_code ec;
  std::filesystem::create_directories(file.parent_path(), ec);
  if (ec)
    throw Error(
        fmt::format("cannot create cache directory {}: {}", file.parent_path().string(), ec.message()));
  const nlohmann::json j = {{"key", sim_tissue_cache_key(spec)},
                            {"displacement_mm", t.displacement_mm},
                            {"load_N", t.load_N},
                            {"transmission", t.transmission},
                            {"transmission_se", t.transmission_stderr},
                            {"seconds", t.seconds}};
  write_file_atomically(file, j.dump(1) + "\n");
}

}  // namespace tocd::mocks
