#include "tocd/mocks/sim_tissue.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "tocd/core/error.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/material/stiffness_scale.hpp"
#include "tocd/sim/study/predictor.hpp"

namespace tocd::mocks {
namespace {

// The published study's fully cleared state relative to native skin (simulation 11).
constexpr double kPublishedMuAFraction = 0.6, kPublishedMuSFraction = 0.6, kPublishedNFraction = 1.1;

// The published cleared state scaled by fraction / published fraction: the same as native x
// fraction, and exactly the published numbers at the published fractions (x / x is 1 in
// floating point, whereas 0.089 x 0.6 is not bit for bit 0.0534), so the default sample's
// tables, and its cache entries, stay what they were.
sim::mc::RegionOptics cleared_optics(const SimTissueSpec& s) {
  sim::mc::RegionOptics c = sim::study::cleared_skin_optics();
  c.mu_a_per_mm *= s.cleared_mu_a_fraction / kPublishedMuAFraction;
  c.mu_s_per_mm *= s.cleared_mu_s_fraction / kPublishedMuSFraction;
  c.n *= s.cleared_n_fraction / kPublishedNFraction;
  return c;
}

void check_spec(const SimTissueSpec& s) {
  if (!(s.thickness_mm > 0))
    throw ConfigError(fmt::format("simulated tissue: thickness {} mm must be > 0", s.thickness_mm));
  if (!(s.stiffness_scale > 0)) throw ConfigError("simulated tissue: stiffness_scale must be > 0");
  const auto positive = [](const char* name, double v) {
    if (!(v > 0) || !std::isfinite(v))
      throw ConfigError(fmt::format("simulated tissue: {} = {} must be finite and > 0", name, v));
  };
  positive("cleared_mu_a_fraction", s.cleared_mu_a_fraction);
  positive("cleared_mu_s_fraction", s.cleared_mu_s_fraction);
  positive("cleared_n_fraction", s.cleared_n_fraction);
  positive("full_clearing_strain", s.full_clearing_strain);
  if (s.displacements_mm.empty()) throw ConfigError("simulated tissue: no displacements to tabulate");
  double last = 0;
  for (double d : s.displacements_mm) {
    if (!(d > last) || !(d < s.thickness_mm))
      throw ConfigError(fmt::format("simulated tissue: displacements must ascend in (0, {}) mm, got {}",
                                    s.thickness_mm, d));
    last = d;
  }
}

}  // namespace

SimTissueOptics sim_tissue_cleared_optics(const SimTissueSpec& spec) {
  const sim::mc::RegionOptics c = cleared_optics(spec);
  return {c.mu_a_per_mm, c.mu_s_per_mm, c.g, c.n};
}

namespace {

SimTissueTable prepare_tables(const SimTissueSpec& spec);

}  // namespace

std::shared_ptr<TissueModel> make_simulated_tissue(const SimTissueSpec& spec, SimTissueTable* table_out) {
  check_spec(spec);
  const auto t0 = std::chrono::steady_clock::now();
  auto say = [&](const std::string& line) {
    if (spec.progress) spec.progress(line);
  };
  SimTissueTable table;
  std::filesystem::path cache_file;
  std::optional<SimTissueTable> cached;
  if (!spec.cache_dir.empty()) {
    cache_file = sim_tissue_cache_file(spec.cache_dir, spec);
    std::string why;
    cached = load_sim_tissue_table(cache_file, spec, why);
    if (!cached) say(fmt::format("simulated sample: preparing ({}: {})", why, cache_file.string()));
  }
  if (cached) {
    table = std::move(*cached);
    table.from_cache = true;
    say(fmt::format("simulated sample: prepared tables from cache {}", cache_file.string()));
  } else {
    table = prepare_tables(spec);
    if (!cache_file.empty()) {
      try {
        store_sim_tissue_table(cache_file, spec, table);
      } catch (const Error& e) {
        say(fmt::format("simulated sample: not cached: {}", e.what()));
      }
    }
  }
  table.cache_file = cache_file.string();
  table.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  auto tissue = make_tabulated_tissue(table.displacement_mm, table.load_N, table.transmission);
  if (table_out) *table_out = std::move(table);
  return tissue;
}

namespace {

// The FE load curve and the Monte Carlo transmission at every tabulated displacement.
SimTissueTable prepare_tables(const SimTissueSpec& spec) {
  auto say = [&](const std::string& line) {
    if (spec.progress) spec.progress(line);
  };
  const sim::material::OgdenParameters material =
      sim::material::scale_stiffness(sim::study::published_skin_material(), spec.stiffness_scale);

  // Load curve: one FE solve through every tabulated displacement.
  sim::fe::FeModel model = sim::fe::FeModel::published_default();
  model.thickness_mm = spec.thickness_mm;
  model.material = material;
  say(fmt::format("simulated sample: FE of {:.2f} mm skin (stiffness x{:.2f}) to {:.3f} mm",
                  spec.thickness_mm, spec.stiffness_scale, spec.displacements_mm.back()));
  const sim::fe::FeResult fe = sim::fe::solve(model, spec.displacements_mm);
  if (!fe.complete || fe.steps.size() != spec.displacements_mm.size())
    throw Error(fmt::format("simulated tissue: FE stopped before {} mm: {}", spec.displacements_mm.back(),
                            fe.stop_reason));

  SimTissueTable table;
  table.displacement_mm.push_back(0.0);
  table.load_N.push_back(0.0);
  for (const auto& step : fe.steps) {
    table.displacement_mm.push_back(step.displacement_mm);
    table.load_N.push_back(step.force_N);
  }

  // Transmission: the Monte Carlo at contact and at each displacement, relative to glass only.
  sim::study::Predictor predictor(1);
  const sim::mc::RegionOptics cleared = cleared_optics(spec);
  auto request = [&](double d) {
    sim::study::PredictionRequest r;
    r.displacement_mm = d;
    r.thickness_mm = spec.thickness_mm;
    r.material = material;
    r.optics_model = spec.optics_model;
    if (spec.optics_model == "threshold") {
      r.compressed_optics = cleared;
      r.compressed_log_strain = -spec.full_clearing_strain;
    }
    r.graded.cleared = cleared;
    r.graded.full_strain = spec.full_clearing_strain;
    r.photons = spec.photons;
    r.seed = spec.seed;
    r.threads = spec.threads;
    return r;
  };
  sim::study::PredictionRequest base_req = request(0.0);
  base_req.baseline = true;
  const sim::study::Prediction base = predictor.predict(base_req);
  if (!(base.T > 0)) throw Error("simulated tissue: glass-only baseline transmits nothing");
  for (double d : table.displacement_mm) {
    const sim::study::Prediction p = predictor.predict(request(d));
    const double T = p.T / base.T;
    const double rel =
        std::sqrt(std::pow(p.T_stderr / std::max(p.T, 1e-300), 2) + std::pow(base.T_stderr / base.T, 2));
    table.transmission.push_back(T);
    table.transmission_stderr.push_back(T * rel);
    say(fmt::format("simulated sample: d = {:.3f} mm  load {:.4f} N  T/T0 {:.4f}", d,
                    table.load_N[table.transmission.size() - 1], T));
  }
  return table;
}

}  // namespace

}  // namespace tocd::mocks
