#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "tocd/core/error.hpp"

namespace tocd::sim::mc {

/// Bad optical properties or optics file; the message names the file, region and key.
using OpticsError = tocd::ErrorOf<struct OpticsInput>;

/// Optical properties of one region at the simulated wavelength.
struct RegionOptics {
  double mu_a_per_mm = 0.0;  ///< absorption coefficient, >= 0
  double mu_s_per_mm = 0.0;  ///< scattering coefficient, >= 0
  double g = 0.0;            ///< Henyey-Greenstein anisotropy, -1 < g <= 1 (1 = no deflection)
  double n = 1.0;            ///< refractive index, > 0
  std::string name;          ///< optional label ("skin")
};

/// Region id (as in TetMesh::regions) -> optical properties.
struct Optics {
  std::map<std::int32_t, RegionOptics> regions;
  /// Refractive index outside the mesh, when the file gives one (`ambient_n`); 0 = not given.
  double ambient_n = 0.0;
};

/// Checks ranges: mu_a, mu_s >= 0 and finite, -1 < g <= 1, n > 0. `where` prefixes messages
/// (e.g. the file name). Throws OpticsError naming the region and the key.
void validate(const Optics& optics, const std::string& where = "optics");

/// Reads a TOML file:
///   ambient_n = 1.0            # optional
///   [region.1]
///   name = "skin"              # optional
///   mu_a = 0.089               # mm^-1
///   mu_s = 28.9                # mm^-1
///   g = 0.926
///   n = 1.38
/// Throws OpticsError naming the file, region and key for a missing or bad value.
Optics load_optics_toml(const std::filesystem::path& path);

/// The same from TOML text (for tests and embedded defaults); `name` labels messages.
Optics parse_optics_toml(const std::string& text, const std::string& name = "optics");

}  // namespace tocd::sim::mc
