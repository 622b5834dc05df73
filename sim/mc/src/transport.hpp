#pragma once
// The photon transport kernel: one packet from entry to termination. Plain data in, tallies
// out; no virtual calls, no allocation, no exceptions, so it can be ported to a GPU as is.

#include <cmath>
#include <cstdint>
#include <numbers>

#include "launcher.hpp"
#include "photon_rng.hpp"
#include "tocd/sim/mc/fresnel.hpp"
#include "tocd/sim/mc/prepared_mesh.hpp"

// The kernel's helper lambdas must inline: out of line (as GCC 12 leaves `interact`), the
// packet's position and direction live in memory and every interaction pays store-to-load
// round trips.
#define TOCD_MC_INLINE __attribute__((always_inline))

namespace tocd::sim::mc {

/// Optical properties of one region in the form the kernel uses.
struct KernelOptics {
  double mu_a, mu_s, mu_t, inv_mu_t, albedo, absorb_fraction;  // absorb_fraction = mu_a/mu_t
  double g, n;
  double hg_one_minus_g2, hg_one_plus_g2, hg_one_minus_g, hg_two_g, hg_inv_two_g;  // HG sampling constants
  int ballistic;  // straight flight with continuous absorption (mu_s ~ 0 or g = 1)
};

struct KernelSettings {
  double ambient_n;
  double roulette_threshold;
  double roulette_chance;
  std::uint64_t max_steps;  // guard against a packet that stops making progress
  bool entry_specular;
  double origin[3];  // kernel coordinates = world coordinates - origin
};

/// Accumulators of one batch. The per-tet array may be null (per-tet tallies off).
struct BatchTally {
  double* absorbed_per_tet;
  double* absorbed_per_region;
  double* exit_per_group;
  double specular = 0.0, missed = 0.0, roulette = 0.0, lost = 0.0;
  std::uint64_t events = 0;
  std::uint64_t face_hits = 0;
};

namespace detail {

// Four doubles in one vector (GCC/Clang vector extension): the per-face arithmetic of a step
// is the same for all four faces, so it is written once for all lanes. Without AVX the
// compiler splits it into SSE2 pairs.
using Lanes4 = double __attribute__((vector_size(32)));
using FloatLanes4 = float __attribute__((vector_size(16)));

[[gnu::always_inline]] inline Lanes4 widen(const float* four) {
  FloatLanes4 f;
  __builtin_memcpy(&f, four, sizeof f);
  return __builtin_convertvector(f, Lanes4);
}

[[gnu::always_inline]] inline double min_lane(Lanes4 v) {
  return std::min(std::min(v[0], v[1]), std::min(v[2], v[3]));
}

// A packet spends ~2 interactions per tet in tissue; its next tet is one of the four
// neighbours. Fetching their records on entry hides the memory latency that otherwise
// dominates every crossing on meshes larger than the cache.
[[gnu::always_inline]] inline void prefetch_neighbours(const KernelTet* tets, const KernelLink* links,
                                                       const KernelLink& here) {
  for (int f = 0; f < 4; ++f) {
    const std::int32_t n = here.next[f] < 0 ? 0 : here.next[f];
    __builtin_prefetch(tets + n);
    __builtin_prefetch(links + n);
  }
}

inline void refract(double* u, const double* m, double eta, double cos_i, double cos_t) {
  // m: unit normal towards the transmission side, u . m = cos_i > 0.
  const double k = cos_t - eta * cos_i;
  for (int c = 0; c < 3; ++c) u[c] = eta * u[c] + k * m[c];
}

// Henyey-Greenstein deflection of u (MCML's formulas, Wang et al. 1995).
[[gnu::always_inline]] inline void scatter(double* u, const KernelOptics& o, PhotonRng& rng) {
  double ct;
  const double xi = rng.uniform();
  if (o.g == 0.0) {
    ct = 2.0 * xi - 1.0;
  } else {
    const double tmp = o.hg_one_minus_g2 / (o.hg_one_minus_g + o.hg_two_g * xi);
    ct = (o.hg_one_plus_g2 - tmp * tmp) * o.hg_inv_two_g;
    ct = ct < -1.0 ? -1.0 : (ct > 1.0 ? 1.0 : ct);
  }
  const double st = std::sqrt(1.0 - ct * ct);
  // Uniform azimuth without trigonometry: a uniform point (x, y) in the unit disk has angle
  // phi with cos(phi) = (x^2 - y^2) / r^2, sin(phi) = 2xy / r^2 (von Neumann). Accepts with
  // probability pi/4; cheaper than sincos and independent of u, so it overlaps the step.
  // x and y take 16 bits each of one draw: a 65536^2 lattice, whose angular granularity
  // (below 1e-4 rad except in the innermost cells, r^2 < 1e-4 rejected) is far below anything
  // a tally resolves.
  double x, y, r2;
  do {
    const std::uint32_t b = rng.bits();
    x = (static_cast<double>(b & 0xffffu) + 0.5) * (2.0 / 65536.0) - 1.0;
    y = (static_cast<double>(b >> 16) + 0.5) * (2.0 / 65536.0) - 1.0;
    r2 = x * x + y * y;
  } while (r2 > 1.0 || r2 < 1e-4);
  const double inv_r2 = 1.0 / r2;
  const double cp = (x * x - y * y) * inv_r2, sp = 2.0 * x * y * inv_r2;
  if (std::abs(u[2]) > 0.99999) {
    u[0] = st * cp;
    u[1] = st * sp;
    u[2] = u[2] > 0.0 ? ct : -ct;
    return;
  }
  const double tmp = std::sqrt(1.0 - u[2] * u[2]);
  const double q = st / tmp;  // one division, not two: without -ffast-math the compiler keeps both
  const double ux = q * (u[0] * u[2] * cp - u[1] * sp) + u[0] * ct;
  const double uy = q * (u[1] * u[2] * cp + u[0] * sp) + u[1] * ct;
  u[2] = -st * cp * tmp + u[2] * ct;
  u[0] = ux;
  u[1] = uy;
}

}  // namespace detail

/// Transports one packet of weight 1 entering at `entry`, until it leaves the mesh, dies in
/// roulette or hits the step guard. Every bit of weight ends in exactly one tally.
inline void transport_photon(const KernelTet* tets, const KernelLink* links, const KernelOptics* optics,
                             const KernelSettings& s, const Entry& entry, PhotonRng& rng, BatchTally& tally) {
  if (entry.tet < 0) {
    tally.missed += 1.0;
    return;
  }
  double w = 1.0;
  double p[3] = {entry.pos[0] - s.origin[0], entry.pos[1] - s.origin[1], entry.pos[2] - s.origin[2]};
  double u[3] = {entry.dir[0], entry.dir[1], entry.dir[2]};
  std::int32_t tet = entry.tet;

  {  // Entry through the ambient/mesh interface: deterministic specular split.
    const KernelTet& k = tets[tet];
    const int f = entry.face;
    const double m[3] = {-k.nx[f], -k.ny[f], -k.nz[f]};
    const double cos_i = u[0] * m[0] + u[1] * m[1] + u[2] * m[2];
    const double n2 = optics[links[tet].region_slot].n;
    double cos_t;
    const double r = fresnel_reflectance(s.ambient_n, n2, cos_i, cos_t);
    if (r >= 1.0) {  // cannot enter at all (denser ambient beyond the critical angle)
      tally.specular += 1.0;
      return;
    }
    if (s.entry_specular) {
      tally.specular += r;
      w = 1.0 - r;
    }
    if (s.ambient_n != n2) detail::refract(u, m, s.ambient_n / n2, cos_i, cos_t);
  }

  // Local copies: the compiler cannot keep tally fields in registers across stores
  // through the tally's arrays.
  double* const absorbed_per_tet = tally.absorbed_per_tet;
  double* const absorbed_per_region = tally.absorbed_per_region;
  double roulette = 0.0;
  std::uint64_t events = 0, face_hits = 0;
  auto deposit = [&](std::int32_t t, std::int32_t slot, double dep) TOCD_MC_INLINE {
    if (absorbed_per_tet) absorbed_per_tet[t] += dep;
    absorbed_per_region[slot] += dep;
  };
  auto finish = [&]() TOCD_MC_INLINE {
    tally.roulette += roulette;
    tally.events += events;
    tally.face_hits += face_hits;
  };

  detail::prefetch_neighbours(tets, links, links[tet]);
  double tau = -std::log(rng.uniform());  // optical depth left to the next interaction
  std::int32_t tet_now = tet;
  // Russian roulette for a light packet: survive 1 in `chance` with `chance` times the
  // weight, so the expected weight is unchanged. Returns false when the packet died.
  auto survives_roulette = [&]() TOCD_MC_INLINE {
    if (w >= s.roulette_threshold) return true;
    if (rng.uniform() * s.roulette_chance < 1.0) {
      roulette -= w * (s.roulette_chance - 1.0);
      w *= s.roulette_chance;
      return true;
    }
    roulette += w;
    finish();
    return false;
  };
  // An interaction at distance `dist` inside the current tet: move, deposit the absorbed
  // fraction (implicit capture), deflect, play roulette, draw the next optical depth.
  // Returns false when the packet died in roulette.
  auto interact = [&](const KernelLink& k, const KernelOptics& o, double dist) TOCD_MC_INLINE {
    for (int c = 0; c < 3; ++c) p[c] += dist * u[c];
    const double dep = w * o.absorb_fraction;
    deposit(tet_now, k.region_slot, dep);
    w -= dep;
    ++events;
    detail::scatter(u, o, rng);
    if (!survives_roulette()) return false;
    tau = -std::log(rng.uniform());
    return true;
  };
  for (std::uint64_t step = 0;; ++step) {
    if (step >= s.max_steps) {
      tally.lost += w;
      finish();
      return;
    }
    tet_now = tet;
    const KernelTet& k = tets[tet];
    const KernelLink& link = links[tet];
    const KernelOptics& o = optics[link.region_slot];
    // cos of the direction with each outward normal, and distance of p inside each plane, for
    // the four faces at once (one vector lane per face).
    const detail::Lanes4 nx = detail::widen(k.nx), ny = detail::widen(k.ny), nz = detail::widen(k.nz);
    const detail::Lanes4 cosf = nx * u[0] + ny * u[1] + nz * u[2];
    const detail::Lanes4 gap = detail::widen(k.offset) - (nx * p[0] + ny * p[1] + nz * p[2]);

    // Fast path, taken by most steps in scattering tissue: the next interaction point
    // p + s u lies inside this tet iff it is inside all four planes. Four multiply-adds and a
    // min, no division and no data-dependent branch per face.
    const double to_event = o.ballistic ? HUGE_VAL : tau * o.inv_mu_t;
    if (!o.ballistic) {
      if (detail::min_lane(gap - to_event * cosf) >= 0.0) {
        if (!interact(link, o, to_event)) return;
        continue;
      }
    }

    // Slow path: the nearest face the packet moves towards. Slightly negative distances
    // (round-off puts p a hair outside a plane) are clamped to 0.
    // Written as selects, not branches: which face wins is unpredictable.
    const detail::Lanes4 q = gap / cosf;
    const detail::Lanes4 zero = {0.0, 0.0, 0.0, 0.0}, never = {HUGE_VAL, HUGE_VAL, HUGE_VAL, HUGE_VAL};
    const detail::Lanes4 d = cosf > zero ? (q > zero ? q : zero) : never;
    const int f01 = d[1] < d[0] ? 1 : 0, f23 = d[3] < d[2] ? 3 : 2;
    const int face = d[f23] < d[f01] ? f23 : f01;
    const double best = d[face];
    if (best == HUGE_VAL) {  // zero direction: cannot happen for unit u, but never loop
      tally.lost += w;
      finish();
      return;
    }
    if (to_event < best) {  // round-off corner: the event is inside after all
      if (!interact(link, o, to_event)) return;
      continue;
    }
    if (o.ballistic) {
      const double dep = w * (1.0 - std::exp(-o.mu_a * best));
      deposit(tet, link.region_slot, dep);
      w -= dep;
      // Also here: a packet trapped by total internal reflection in weakly absorbing glass
      // would otherwise bounce until the step guard.
      if (!survives_roulette()) return;
    } else {
      tau -= best * o.mu_t;
    }

    // Move to the face and cross it, or reflect off it.
    ++face_hits;
    for (int c = 0; c < 3; ++c) p[c] += best * u[c];
    const std::int32_t next = link.next[face];
    const double n1 = o.n;
    const double n2 = next >= 0 ? optics[link.next_slot[face]].n : s.ambient_n;
    if (n1 != n2) {
      const double m[3] = {k.nx[face], k.ny[face], k.nz[face]};
      const double cos_i = cosf[face];
      double cos_t;
      const double r = fresnel_reflectance(n1, n2, cos_i, cos_t);
      if (r >= 1.0 || rng.uniform() < r) {
        for (int c = 0; c < 3; ++c) u[c] -= 2.0 * cos_i * m[c];
        continue;
      }
      detail::refract(u, m, n1 / n2, cos_i, cos_t);
    }
    if (next < 0) {
      tally.exit_per_group[-1 - next] += w;
      finish();
      return;
    }
    tet = next;
    detail::prefetch_neighbours(tets, links, links[tet]);
    if (absorbed_per_tet) __builtin_prefetch(absorbed_per_tet + tet, 1);  // the next deposit goes here
  }
}

}  // namespace tocd::sim::mc
