#pragma once

// The simulated sample's prepared tables on disk, so that a second `tocdlab demo` with the
// same sample starts recording at once instead of re-running the FE and the Monte Carlo.
// An entry is keyed by the full configuration that determines the tables (every field of
// SimTissueSpec that changes a number, and the tocdlab version, whose model may change); the
// file stores that key in full and is used only when it matches exactly and every number is
// sane. Anything else (absent, unreadable, truncated, edited, another key) is rebuilt.

#include <filesystem>
#include <optional>
#include <string>

#include "tocd/mocks/sim_tissue.hpp"

namespace tocd::mocks {

/// $TOCDLAB_CACHE_DIR, else $XDG_CACHE_HOME/tocdlab, else $HOME/.cache/tocdlab; empty when
/// none of them is set (no cache).
std::filesystem::path default_sim_tissue_cache_dir();

/// The canonical text of everything that determines the tables (threads and progress do not).
std::string sim_tissue_cache_key(const SimTissueSpec& spec);

/// dir/sim-sample-<16 hex digits of a 64-bit FNV-1a hash of the key>.json
std::filesystem::path sim_tissue_cache_file(const std::filesystem::path& dir, const SimTissueSpec& spec);

/// The cached tables for `spec`, or nullopt with `why` saying what was wrong (absent, not
/// JSON, another key, inconsistent numbers). Never throws for a bad file.
std::optional<SimTissueTable> load_sim_tissue_table(const std::filesystem::path& file,
                                                    const SimTissueSpec& spec, std::string& why);

/// Writes the tables for `spec` atomically (the file appears complete or not at all), creating
/// the directory. Throws tocd::Error naming the file when it cannot be written.
void store_sim_tissue_table(const std::filesystem::path& file, const SimTissueSpec& spec,
                            const SimTissueTable& table);

}  // namespace tocd::mocks
