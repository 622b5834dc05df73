#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "tocd/db/reader.hpp"
#include "tocd/sim/fe/inverse_fit.hpp"

namespace tocd::analysis {

/// Which of a run's loads an FE fit matches (`tocdlab fit --method fe --points`, docs/fe.md).
///  - held: each completed step's load, averaged over its recording window in the hold, at the
///    displacement the tester reported there. The FE law is elastic: these are the run's
///    loads nearest equilibrium, and the loads the step table compares with.
///  - loading: the loading curve (new deepest readings only, binned in strain). It carries the
///    rate-dependent overstress a biphasic sample builds while the pin moves, so an elastic law
///    fitted to it comes out stiffer than the held loads say.
enum class RunLoadPoints { held, loading };

RunLoadPoints parse_run_load_points(const std::string& s);  ///< throws ConfigError naming s
const char* to_string(RunLoadPoints p);

/// A run's load/displacement points as FE fit data; `model` gets the run's sample thickness
/// (unless `thickness_mm` > 0 overrides it) and `pin_radius_mm`. `bins`: strain bins of the
/// loading curve. Throws tocd::Error when the run lacks a thickness, load or displacement, or
/// gives fewer than two points.
sim::fe::PinCompressionData pin_data_from_run(const db::Reader& reader, std::int64_t run_id,
                                              RunLoadPoints points, double pin_radius_mm,
                                              std::size_t bins = 16, double thickness_mm = 0);

}  // namespace tocd::analysis
