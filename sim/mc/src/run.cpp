// Batching, threading and reduction around the transport kernel. A batch is a fixed,
// contiguous range of photon indices; batches run in waves of `threads`, and the master
// adds finished batches into the totals in batch order. With one random stream per photon
// this makes every tally bitwise identical whatever the thread count.
#include "tocd/sim/mc/run.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <omp.h>

#include "launcher.hpp"
#include "tocd/core/clock.hpp"
#include "transport.hpp"

namespace tocd::sim::mc {
namespace {

// Tallies of one batch, owned by one wave slot.
struct BatchStore {
  std::vector<double, HugePageAllocator<double>> per_tet;  // randomly hit: huge pages
  std::vector<double> per_region, per_group;
  BatchTally tally{};
  std::uint64_t photons = 0;

  void reset(std::size_t nt, std::size_t nr, std::size_t ng) {
    per_tet.assign(nt, 0.0);
    per_region.assign(nr, 0.0);
    per_group.assign(ng, 0.0);
    tally = BatchTally{nt ? per_tet.data() : nullptr, per_region.data(), per_group.data()};
    photons = 0;
  }
};

// Running sums over batches of x_b (batch total) and x_b^2 / n_b, for mean and SE.
struct Accumulator {
  double sum = 0.0, sum_sq_per_n = 0.0;
  void add(double x, std::uint64_t n) {
    sum += x;
    sum_sq_per_n += x * x / static_cast<double>(n);
  }
  Estimate estimate(std::uint64_t total, int batches) const {
    Estimate e;
    if (total == 0) return e;
    const double nt = static_cast<double>(total);
    e.mean = sum / nt;
    if (batches > 1) {
      // sum_b n_b (m_b - m)^2 / (B - 1) estimates the per-photon variance.
      const double spread = std::max(0.0, sum_sq_per_n - nt * e.mean * e.mean);
      e.se = std::sqrt(spread / (batches - 1) / nt);
    }
    return e;
  }
};

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

void check_settings(const RunSettings& s) {
  if (s.photons == 0) throw tocd::ConfigError("photons must be > 0");
  if (s.batches < 2)
    throw tocd::ConfigError(fmt::format("batches = {} must be >= 2 for standard errors", s.batches));
  if (static_cast<std::uint64_t>(s.batches) > s.photons) throw tocd::ConfigError("more batches than photons");
  if (s.threads < 1) throw tocd::ConfigError(fmt::format("threads = {} must be >= 1", s.threads));
  if (!(s.ambient_n > 0.0)) throw tocd::ConfigError(fmt::format("ambient_n = {} must be > 0", s.ambient_n));
  if (!(s.roulette_threshold > 0.0 && s.roulette_threshold < 1.0) || s.roulette_chance < 2) {
    throw tocd::ConfigError("roulette threshold must lie in (0, 1) and roulette chance be >= 2");
  }
}

}  // namespace

Result run(const PreparedMesh& mesh, const Optics& optics, const Source& source,
           const RunSettings& settings) {
  check_settings(settings);
  const std::vector<KernelOptics> kopt = kernel_optics(mesh, optics, settings);
  const Launcher launcher(mesh, source);
  const KernelSettings ks{settings.ambient_n,
                          settings.roulette_threshold,
                          static_cast<double>(settings.roulette_chance),
                          std::uint64_t{10'000'000},
                          source.entry_specular,
                          {mesh.origin[0], mesh.origin[1], mesh.origin[2]}};

  const std::size_t nt = settings.tally_per_tet ? mesh.tets.size() : 0;
  const std::size_t nr = kopt.size(), ng = mesh.groups.size();
  const int batches = settings.batches;
  const int threads = std::min(settings.threads, batches);
  const std::uint64_t n = settings.photons;
  auto batch_begin = [&](int b) {
    return n * static_cast<std::uint64_t>(b) / static_cast<std::uint64_t>(batches);
  };

  Accumulator specular, missed, roulette, lost, bottom, top, sides, absorbed;
  std::map<std::int32_t, Accumulator> by_marker;
  for (const auto& g : mesh.groups) by_marker[g.marker];
  std::vector<Accumulator> per_tet(nt), per_region(nr), per_group(ng);
  std::vector<BatchStore> slots(static_cast<std::size_t>(threads));
  std::atomic<std::uint64_t> done{0};
  std::atomic<bool> stop{false};
  std::uint64_t launched = 0, events = 0, face_hits = 0;
  int batches_done = 0;

  const std::int64_t t0 = tocd::monotonic_ns();
  for (int wave = 0; wave < batches && !stop.load(); wave += threads) {
    const int in_wave = std::min(threads, batches - wave);
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int i = 0; i < in_wave; ++i) {
      BatchStore& slot = slots[static_cast<std::size_t>(i)];
      slot.reset(nt, nr, ng);
      const std::uint64_t first = batch_begin(wave + i), last = batch_begin(wave + i + 1);
      std::uint64_t photon = first;
      auto next_photon = [&](PhotonRng& rng, Entry& entry) {
        if (photon == last) return false;
        if (((photon - first) & 1023u) == 0 && photon != first) {
          done.fetch_add(1024, std::memory_order_relaxed);
          if (settings.cancel && settings.cancel->load(std::memory_order_relaxed)) stop.store(true);
          if (stop.load(std::memory_order_relaxed)) return false;
          if (settings.progress && omp_get_thread_num() == 0) settings.progress(done.load(), n);
        }
        rng = PhotonRng(settings.seed, photon);
        entry = launcher.sample(rng);
        ++photon;
        ++slot.photons;
        return true;
      };
      transport_batch(mesh.tets.data(), mesh.links.data(), kopt.data(), ks, slot.tally, next_photon);
    }
    if (stop.load()) break;  // a cancelled wave is incomplete: keep only whole batches
    for (int i = 0; i < in_wave; ++i) {
      const BatchStore& b = slots[static_cast<std::size_t>(i)];
      specular.add(b.tally.specular, b.photons);
      missed.add(b.tally.missed, b.photons);
      roulette.add(b.tally.roulette, b.photons);
      lost.add(b.tally.lost, b.photons);
      for (std::size_t t = 0; t < nt; ++t) per_tet[t].add(b.per_tet[t], b.photons);
      for (std::size_t r = 0; r < nr; ++r) per_region[r].add(b.per_region[r], b.photons);
      for (std::size_t g = 0; g < ng; ++g) per_group[g].add(b.per_group[g], b.photons);
      // Sides, markers and total absorption are combined per batch so that their standard
      // errors come from batch totals too.
      double side_sum[3] = {0.0, 0.0, 0.0}, absorbed_sum = 0.0;
      std::map<std::int32_t, double> marker_sum;
      for (std::size_t g = 0; g < ng; ++g) {
        side_sum[static_cast<int>(mesh.groups[g].side)] += b.per_group[g];
        marker_sum[mesh.groups[g].marker] += b.per_group[g];
      }
      for (std::size_t r = 0; r < nr; ++r) absorbed_sum += b.per_region[r];
      bottom.add(side_sum[static_cast<int>(Side::bottom)], b.photons);
      top.add(side_sum[static_cast<int>(Side::top)], b.photons);
      sides.add(side_sum[static_cast<int>(Side::sides)], b.photons);
      absorbed.add(absorbed_sum, b.photons);
      for (const auto& [marker, w] : marker_sum) by_marker[marker].add(w, b.photons);
      launched += b.photons;
      events += b.tally.events;
      face_hits += b.tally.face_hits;
      ++batches_done;
    }
    if (settings.progress) settings.progress(launched, n);
  }
  const double seconds = static_cast<double>(tocd::monotonic_ns() - t0) * 1e-9;

  Result res;
  res.photons = launched;
  res.seed = settings.seed;
  res.threads = threads;
  res.batches = batches_done;
  res.cancelled = stop.load();
  res.specular = specular.estimate(launched, batches_done);
  res.missed = missed.estimate(launched, batches_done);
  res.roulette_balance = roulette.estimate(launched, batches_done);
  res.lost = lost.estimate(launched, batches_done);

  res.transmittance = bottom.estimate(launched, batches_done);
  res.reflectance = top.estimate(launched, batches_done);
  res.side_loss = sides.estimate(launched, batches_done);
  res.absorbed = absorbed.estimate(launched, batches_done);
  for (const auto& [marker, acc] : by_marker)
    res.exit_by_marker[marker] = acc.estimate(launched, batches_done);
  for (std::size_t r = 0; r < nr; ++r) {
    res.absorbed_by_region[mesh.region_ids[r]] = per_region[r].estimate(launched, batches_done);
  }
  if (nt > 0) {
    res.absorbed_per_tet.resize(nt);
    res.absorbed_per_tet_se.resize(nt);
    res.fluence_per_tet.assign(nt, 0.0);
    res.fluence_per_tet_se.assign(nt, 0.0);
    for (std::size_t kt = 0; kt < nt; ++kt) {  // kernel order -> input order
      const auto t = static_cast<std::size_t>(mesh.original_of[kt]);
      const Estimate e = per_tet[kt].estimate(launched, batches_done);
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
    const double accounted =
        specular.sum + bottom.sum + top.sum + sides.sum + absorbed.sum + roulette.sum + missed.sum + lost.sum;
    res.energy_balance_error = (static_cast<double>(launched) - accounted) / static_cast<double>(launched);
  }
  res.seconds = seconds;
  res.events = events;
  res.face_hits = face_hits;
  res.photons_per_second = seconds > 0 ? static_cast<double>(launched) / seconds : 0.0;
  res.events_per_second = seconds > 0 ? static_cast<double>(events) / seconds : 0.0;
  return res;
}

}  // namespace tocd::sim::mc
