// Batching, threading and reduction around the transport kernel. A batch is a fixed,
// contiguous range of photon indices; batches run in waves of `threads`, and the master adds
// each finished batch's totals into exact (fixed-point, order-free) sums. With one random
// stream per photon this makes every tally bitwise identical whatever the thread count and
// however the batches are shared among MPI ranks.
#include "tocd/sim/mc/run.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <fmt/format.h>
#include <omp.h>

#include "exact_sum.hpp"
#include "launcher.hpp"
#include "tocd/core/clock.hpp"
#include "tocd/core/isa_dispatch.hpp"
#include "transport.hpp"

namespace tocd::sim::mc {
namespace {

// Tallies of one batch, owned by one wave slot.
struct BatchStore {
  std::vector<double, HugePageAllocator<double>> per_tet;  // randomly hit: huge pages
  std::vector<double> per_region, per_group;
  std::vector<double> dT_dmu_a, dT_dmu_s, path_scratch;  // transmittance derivatives only
  BatchTally tally{};
  std::uint64_t photons = 0;

  // `transmittance_group`: per boundary group, 1 where exits count as transmittance; null
  // when the run does not ask for derivatives.
  void reset(std::size_t nt, std::size_t nr, std::size_t ng, const std::uint8_t* transmittance_group) {
    per_tet.assign(nt, 0.0);
    per_region.assign(nr, 0.0);
    per_group.assign(ng, 0.0);
    tally = BatchTally{nt ? per_tet.data() : nullptr, per_region.data(), per_group.data()};
    if (transmittance_group) {
      dT_dmu_a.assign(nr, 0.0);
      dT_dmu_s.assign(nr, 0.0);
      path_scratch.assign(2 * nr * kPacketsInFlight, 0.0);
      tally.dT_dmu_a_per_region = dT_dmu_a.data();
      tally.dT_dmu_s_per_region = dT_dmu_s.data();
      tally.transmittance_group = transmittance_group;
      tally.path_scratch = path_scratch.data();
      tally.regions = static_cast<std::int32_t>(nr);
    }
    photons = 0;
  }
};

// Where each tallied quantity sits in a run's exact tallies. A quantity estimated from batch
// totals x_b takes two fixed-point numbers: sum_b x_b and sum_b x_b^2 / n_b. After them come
// plain integer counts. With transmittance derivatives, dT/dmu_a and dT/dmu_s per region
// follow the per-tet quantities.
struct TallyLayout {
  static constexpr int kPerQuantity = 2 * kExactLimbs;
  enum Scalar { specular, missed, roulette, lost, bottom, top, sides, absorbed, kScalars };
  enum Count { launched, batches, events, face_hits, cancelled, kCounts };
  std::vector<std::int32_t> markers;   // ascending
  std::size_t nr = 0, nt = 0, nd = 0;  // nd: regions with derivatives (0 or nr)

  TallyLayout(const PreparedMesh& mesh, std::size_t regions, bool per_tet, bool derivatives)
      : nr(regions), nt(per_tet ? mesh.tets.size() : 0), nd(derivatives ? regions : 0) {
    for (const auto& g : mesh.groups) markers.push_back(g.marker);
    std::sort(markers.begin(), markers.end());
    markers.erase(std::unique(markers.begin(), markers.end()), markers.end());
  }
  std::size_t quantities() const { return kScalars + markers.size() + nr + nt + 2 * nd; }
  std::size_t scalar(int s) const { return static_cast<std::size_t>(s); }
  std::size_t marker(std::size_t i) const { return kScalars + i; }
  std::size_t region(std::size_t r) const { return kScalars + markers.size() + r; }
  std::size_t tet(std::size_t kt) const { return kScalars + markers.size() + nr + kt; }
  std::size_t dT_dmu_a(std::size_t r) const { return kScalars + markers.size() + nr + nt + r; }
  std::size_t dT_dmu_s(std::size_t r) const { return kScalars + markers.size() + nr + nt + nd + r; }
  std::size_t count(int c) const { return quantities() * kPerQuantity + static_cast<std::size_t>(c); }
  std::size_t words() const { return quantities() * kPerQuantity + kCounts; }
};

// Adds one batch's total x of quantity q (n photons in the batch) to the tallies.
void add_batch_total(std::int64_t* words, std::size_t q, double x, std::uint64_t n) {
  std::int64_t* w = words + q * TallyLayout::kPerQuantity;
  exact_add(x, w);
  exact_add(x * x / static_cast<double>(n), w + kExactLimbs);
}

// Mean and standard error of quantity q over `total` photons in `batches` batches.
Estimate estimate(const std::int64_t* words, std::size_t q, std::uint64_t total, std::int64_t batches) {
  Estimate e;
  if (total == 0) return e;
  const std::int64_t* w = words + q * TallyLayout::kPerQuantity;
  const double sum = exact_value(w), sum_sq_per_n = exact_value(w + kExactLimbs);
  const double nt = static_cast<double>(total);
  e.mean = sum / nt;
  if (batches > 1) {
    // sum_b n_b (m_b - m)^2 / (B - 1) estimates the per-photon variance.
    const double spread = std::max(0.0, sum_sq_per_n - nt * e.mean * e.mean);
    e.se = std::sqrt(spread / static_cast<double>(batches - 1) / nt);
  }
  return e;
}

std::vector<KernelOptics> kernel_optics(const PreparedMesh& mesh, const Optics& optics,
                                        const RunSettings& s) {
  validate(optics);
  std::vector<KernelOptics> out;
  for (const auto id : mesh.region_ids) {
    const auto it = optics.regions.find(id);
    if (it == optics.regions.end()) {
      const auto count = std::count(mesh.mesh.regions.begin(), mesh.mesh.regions.end(), id);
      throw OpticsError(
          fmt::format("region {} ({} tets) has no optical properties: add a [region.{}] table to the optics",
                      id, count, id));
    }
    const RegionOptics& r = it->second;
    KernelOptics k{};
    k.mu_a = r.mu_a_per_mm;
    k.mu_s = r.mu_s_per_mm;
    k.mu_t = k.mu_a + k.mu_s;
    k.g = r.g;
    k.n = r.n;
    k.ballistic = (k.mu_s <= s.ballistic_mu_s_per_mm || r.g == 1.0) ? 1 : 0;
    k.inv_mu_t = k.ballistic ? 0.0 : 1.0 / k.mu_t;
    k.absorb_fraction = k.ballistic ? 0.0 : k.mu_a / k.mu_t;
    k.hg_one_minus_g2 = 1.0 - k.g * k.g;
    k.hg_one_plus_g2 = 1.0 + k.g * k.g;
    k.hg_one_minus_g = 1.0 - k.g;
    k.hg_two_g = 2.0 * k.g;
    k.hg_inv_two_g = k.g == 0.0 ? 0.0 : 1.0 / (2.0 * k.g);
    out.push_back(k);
  }
  return out;
}

// The photons of one batch, [first, last), and the run's sizes for progress reports.
struct BatchRange {
  std::uint64_t first, last;
  std::uint64_t run_photons, member_photons;  // the whole run's, this team member's
};

// Shared by the threads of a run: photons done, and whether to stop (cancelled).
struct BatchProgress {
  std::atomic<std::uint64_t> done{0};
  std::atomic<bool> stop{false};
};

// Everything a batch needs from its run.
struct BatchJob {
  const PreparedMesh& mesh;
  const KernelOptics* kopt;
  const KernelSettings& ks;
  const Launcher& launcher;
  const RunSettings& settings;
  BatchRange range;
  BatchProgress& progress;
};

// Transports the photons of one batch into `slot`. The whole photon loop, transport_batch
// inlined, sits in this body so that each ISA version of run_batch holds the complete hot
// path: a version of a thin wrapper around an out-of-line kernel would gain nothing.
template <bool kDerivatives>
[[gnu::always_inline]] inline void run_batch_body(const BatchJob& job, BatchStore& slot) {
  const RunSettings& settings = job.settings;
  BatchProgress& progress = job.progress;
  const std::uint64_t first = job.range.first, last = job.range.last, n = job.range.run_photons;
  std::uint64_t photon = first;
  auto next_photon = [&](PhotonRng& rng, Entry& entry) {
    if (photon == last) return false;
    if (((photon - first) & 1023u) == 0 && photon != first) {
      progress.done.fetch_add(1024, std::memory_order_relaxed);
      if (settings.cancel && settings.cancel->load(std::memory_order_relaxed)) progress.stop.store(true);
      if (progress.stop.load(std::memory_order_relaxed)) return false;
      // This member's share, scaled to the whole run: the others progress alike.
      if (settings.progress && omp_get_thread_num() == 0)
        settings.progress(std::min(n, progress.done.load() * n / job.range.member_photons), n);
    }
    rng = PhotonRng(settings.seed, photon);
    entry = job.launcher.sample(rng);
    ++photon;
    ++slot.photons;
    return true;
  };
  transport_batch<kDerivatives>(job.mesh.tets.data(), job.mesh.links.data(), job.kopt, job.ks, slot.tally,
                                next_photon);
}

// Both kernels, plain and with the derivative records, in every ISA version.
[[gnu::always_inline]] inline void run_batch_either(const BatchJob& job, BatchStore& slot) {
  if (job.settings.transmittance_derivatives)
    run_batch_body<true>(job, slot);
  else
    run_batch_body<false>(job, slot);
}

// The batch kernel for AVX-512, AVX2 and the baseline, picked when the program starts
// (tocd/core/isa_dispatch.hpp).
#if TOCD_ISA_VERSIONS
TOCD_ISA_V4 void run_batch(const BatchJob& job, BatchStore& slot) {
  run_batch_either(job, slot);
}
TOCD_ISA_V3 void run_batch(const BatchJob& job, BatchStore& slot) {
  run_batch_either(job, slot);
}
#endif
TOCD_ISA_BASE void run_batch(const BatchJob& job, BatchStore& slot) {
  run_batch_either(job, slot);
}

void check_settings(const RunSettings& s) {
  if (s.photons == 0) throw tocd::ConfigError("photons must be > 0");
  if (s.batches < 2)
    throw tocd::ConfigError(fmt::format("batches = {} must be >= 2 for standard errors", s.batches));
  if (static_cast<std::uint64_t>(s.batches) > s.photons) throw tocd::ConfigError("more batches than photons");
  if (s.photons > (std::uint64_t{1} << 53))
    throw tocd::ConfigError(fmt::format("photons = {} exceeds the limit of 2^53 (9.0e15)", s.photons));
  if (s.batches > (1 << 24))
    throw tocd::ConfigError(fmt::format("batches = {} exceeds the limit of 2^24", s.batches));
  if (s.threads < 1) throw tocd::ConfigError(fmt::format("threads = {} must be >= 1", s.threads));
  if (!(s.ambient_n > 0.0)) throw tocd::ConfigError(fmt::format("ambient_n = {} must be > 0", s.ambient_n));
  if (!(s.roulette_threshold > 0.0 && s.roulette_threshold < 1.0) || s.roulette_chance < 2) {
    throw tocd::ConfigError("roulette threshold must lie in (0, 1) and roulette chance be >= 2");
  }
}

}  // namespace

Tallies run_batches(const PreparedMesh& mesh, const Optics& optics, const Source& source,
                    const RunSettings& settings, int first_batch, int last_batch) {
  check_settings(settings);
  if (first_batch < 0 || last_batch > settings.batches || first_batch > last_batch)
    throw tocd::ConfigError(fmt::format("batches [{}, {}) lie outside the run's {} batches", first_batch,
                                        last_batch, settings.batches));
  const std::vector<KernelOptics> kopt = kernel_optics(mesh, optics, settings);
  const Launcher launcher(mesh, source);
  const KernelSettings ks{settings.ambient_n,
                          settings.roulette_threshold,
                          static_cast<double>(settings.roulette_chance),
                          std::uint64_t{10'000'000},
                          source.entry_specular,
                          {mesh.origin[0], mesh.origin[1], mesh.origin[2]}};

  const TallyLayout layout(mesh, kopt.size(), settings.tally_per_tet, settings.transmittance_derivatives);
  const std::size_t nt = layout.nt, nr = kopt.size(), ng = mesh.groups.size();
  const int batches = settings.batches;
  const int mine = last_batch - first_batch;
  const int threads = std::max(1, std::min(settings.threads, mine));
  const std::uint64_t n = settings.photons;
  auto batch_begin = [&](int b) {
    return n * static_cast<std::uint64_t>(b) / static_cast<std::uint64_t>(batches);
  };
  const std::uint64_t my_photons = batch_begin(last_batch) - batch_begin(first_batch);

  Tallies out;
  out.words.assign(layout.words(), 0);
  std::int64_t* w = out.words.data();
  std::vector<std::size_t> marker_slot(ng);  // boundary group -> index in layout.markers
  for (std::size_t g = 0; g < ng; ++g)
    marker_slot[g] = static_cast<std::size_t>(
        std::lower_bound(layout.markers.begin(), layout.markers.end(), mesh.groups[g].marker) -
        layout.markers.begin());
  std::vector<std::uint8_t> transmittance_group(ng);
  for (std::size_t g = 0; g < ng; ++g) transmittance_group[g] = mesh.groups[g].side == Side::bottom ? 1 : 0;
  const std::uint8_t* derivative_groups =
      settings.transmittance_derivatives ? transmittance_group.data() : nullptr;
  std::vector<BatchStore> slots(static_cast<std::size_t>(threads));
  BatchProgress progress;
  std::atomic<bool>& stop = progress.stop;

  for (int wave = first_batch; wave < last_batch && !stop.load(); wave += threads) {
    const int in_wave = std::min(threads, last_batch - wave);
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int i = 0; i < in_wave; ++i) {
      BatchStore& slot = slots[static_cast<std::size_t>(i)];
      slot.reset(nt, nr, ng, derivative_groups);
      const BatchRange range{batch_begin(wave + i), batch_begin(wave + i + 1), n, my_photons};
      run_batch(BatchJob{mesh, kopt.data(), ks, launcher, settings, range, progress}, slot);
    }
    if (stop.load()) break;  // a cancelled wave is incomplete: keep only whole batches
    for (int i = 0; i < in_wave; ++i) {
      const BatchStore& b = slots[static_cast<std::size_t>(i)];
      auto add = [&](std::size_t q, double x) { add_batch_total(w, q, x, b.photons); };
      add(layout.scalar(TallyLayout::specular), b.tally.specular);
      add(layout.scalar(TallyLayout::missed), b.tally.missed);
      add(layout.scalar(TallyLayout::roulette), b.tally.roulette);
      add(layout.scalar(TallyLayout::lost), b.tally.lost);
      for (std::size_t t = 0; t < nt; ++t) add(layout.tet(t), b.per_tet[t]);
      for (std::size_t r = 0; r < layout.nd; ++r) {
        add(layout.dT_dmu_a(r), b.dT_dmu_a[r]);
        add(layout.dT_dmu_s(r), b.dT_dmu_s[r]);
      }
      // Sides, markers and total absorption are combined per batch so that their standard
      // errors come from batch totals too.
      double side_sum[3] = {0.0, 0.0, 0.0}, absorbed_sum = 0.0;
      std::vector<double> marker_sum(layout.markers.size(), 0.0);
      for (std::size_t g = 0; g < ng; ++g) {
        side_sum[static_cast<int>(mesh.groups[g].side)] += b.per_group[g];
        marker_sum[marker_slot[g]] += b.per_group[g];
      }
      for (std::size_t r = 0; r < nr; ++r) {
        add(layout.region(r), b.per_region[r]);
        absorbed_sum += b.per_region[r];
      }
      add(layout.scalar(TallyLayout::bottom), side_sum[static_cast<int>(Side::bottom)]);
      add(layout.scalar(TallyLayout::top), side_sum[static_cast<int>(Side::top)]);
      add(layout.scalar(TallyLayout::sides), side_sum[static_cast<int>(Side::sides)]);
      add(layout.scalar(TallyLayout::absorbed), absorbed_sum);
      for (std::size_t m = 0; m < marker_sum.size(); ++m) add(layout.marker(m), marker_sum[m]);
      w[layout.count(TallyLayout::launched)] += static_cast<std::int64_t>(b.photons);
      w[layout.count(TallyLayout::events)] += static_cast<std::int64_t>(b.tally.events);
      w[layout.count(TallyLayout::face_hits)] += static_cast<std::int64_t>(b.tally.face_hits);
      w[layout.count(TallyLayout::batches)] += 1;
    }
    if (settings.progress) {
      const auto launched = static_cast<std::uint64_t>(w[layout.count(TallyLayout::launched)]);
      settings.progress(std::min(n, launched * n / my_photons), n);
    }
  }
  w[layout.count(TallyLayout::cancelled)] = stop.load() ? 1 : 0;
  out.threads = threads;
  return out;
}

Result finish(const PreparedMesh& mesh, const Optics& optics, const RunSettings& settings,
              const Tallies& tallies) {
  const std::vector<KernelOptics> kopt = kernel_optics(mesh, optics, settings);
  const TallyLayout layout(mesh, kopt.size(), settings.tally_per_tet, settings.transmittance_derivatives);
  if (tallies.words.size() != layout.words())
    throw tocd::Error(fmt::format("Monte Carlo tallies of {} words do not fit this run ({} expected)",
                                  tallies.words.size(), layout.words()));
  const std::int64_t* w = tallies.words.data();
  const auto launched = static_cast<std::uint64_t>(w[layout.count(TallyLayout::launched)]);
  const std::int64_t batches = w[layout.count(TallyLayout::batches)];
  auto est = [&](std::size_t q) { return estimate(w, q, launched, batches); };

  Result res;
  res.photons = launched;
  res.seed = settings.seed;
  res.threads = tallies.threads;
  res.batches = static_cast<int>(batches);
  res.cancelled = w[layout.count(TallyLayout::cancelled)] != 0;
  res.specular = est(layout.scalar(TallyLayout::specular));
  res.missed = est(layout.scalar(TallyLayout::missed));
  res.roulette_balance = est(layout.scalar(TallyLayout::roulette));
  res.lost = est(layout.scalar(TallyLayout::lost));
  res.transmittance = est(layout.scalar(TallyLayout::bottom));
  res.reflectance = est(layout.scalar(TallyLayout::top));
  res.side_loss = est(layout.scalar(TallyLayout::sides));
  res.absorbed = est(layout.scalar(TallyLayout::absorbed));
  for (std::size_t m = 0; m < layout.markers.size(); ++m)
    res.exit_by_marker[layout.markers[m]] = est(layout.marker(m));
  for (std::size_t r = 0; r < layout.nr; ++r)
    res.absorbed_by_region[mesh.region_ids[r]] = est(layout.region(r));
  for (std::size_t r = 0; r < layout.nd; ++r)
    res.transmittance_derivatives[mesh.region_ids[r]] = {est(layout.dT_dmu_a(r)), est(layout.dT_dmu_s(r))};
  const std::size_t nt = layout.nt;
  if (nt > 0) {
    res.absorbed_per_tet.resize(nt);
    res.absorbed_per_tet_se.resize(nt);
    res.fluence_per_tet.assign(nt, 0.0);
    res.fluence_per_tet_se.assign(nt, 0.0);
    for (std::size_t kt = 0; kt < nt; ++kt) {  // kernel order -> input order
      const auto t = static_cast<std::size_t>(mesh.original_of[kt]);
      const Estimate e = est(layout.tet(kt));
      res.absorbed_per_tet[t] = e.mean;
      res.absorbed_per_tet_se[t] = e.se;
      const double mu_a = kopt[static_cast<std::size_t>(mesh.links[kt].region_slot)].mu_a;
      if (mu_a > 0.0) {
        res.fluence_per_tet[t] = e.mean / (mesh.volume_mm3[t] * mu_a);
        res.fluence_per_tet_se[t] = e.se / (mesh.volume_mm3[t] * mu_a);
      }
    }
  }
  if (launched > 0) {
    double accounted = 0.0;
    for (int s : {TallyLayout::specular, TallyLayout::bottom, TallyLayout::top, TallyLayout::sides,
                  TallyLayout::absorbed, TallyLayout::roulette, TallyLayout::missed, TallyLayout::lost})
      accounted += exact_value(w + layout.scalar(s) * TallyLayout::kPerQuantity);
    res.energy_balance_error = (static_cast<double>(launched) - accounted) / static_cast<double>(launched);
  }
  res.events = static_cast<std::uint64_t>(w[layout.count(TallyLayout::events)]);
  res.face_hits = static_cast<std::uint64_t>(w[layout.count(TallyLayout::face_hits)]);
  return res;
}

Result run(const PreparedMesh& mesh, const Optics& optics, const Source& source,
           const RunSettings& settings) {
  check_settings(settings);
  parallel::Team& team = settings.team ? *settings.team : parallel::solo();
  const std::int64_t t0 = tocd::monotonic_ns();
  // Member r runs the r-th contiguous block of batches; which member ran a batch never
  // changes its photons, and the exact sum makes the order of combination irrelevant.
  const auto share = [&](int r) {
    return static_cast<int>(static_cast<std::int64_t>(settings.batches) * r / team.size());
  };
  Tallies tallies = run_batches(mesh, optics, source, settings, share(team.rank()), share(team.rank() + 1));
  const int threads = tallies.threads;
  team.sum(tallies.words);
  tallies.threads = threads;
  Result res = finish(mesh, optics, settings, tallies);
  res.ranks = team.size();
  res.seconds = static_cast<double>(tocd::monotonic_ns() - t0) * 1e-9;
  res.photons_per_second = res.seconds > 0 ? static_cast<double>(res.photons) / res.seconds : 0.0;
  res.events_per_second = res.seconds > 0 ? static_cast<double>(res.events) / res.seconds : 0.0;
  return res;
}

}  // namespace tocd::sim::mc
