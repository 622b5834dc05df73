#pragma once
// The photon transport kernel: packets from entry to termination. Plain data in, tallies
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
  double mu_a, mu_s, mu_t, inv_mu_t, absorb_fraction;  // absorb_fraction = mu_a/mu_t
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
  // Transmittance derivatives (read only by the kernel's derivative version): per region
  // slot, sum of w * dlog(w)/dmu_a and w * dlog(w)/dmu_s over the packets that exit through
  // a transmittance face; which boundary groups those are; and scratch for the path records
  // of the packets in flight (kPacketsInFlight * 2 * regions doubles).
  double* dT_dmu_a_per_region = nullptr;
  double* dT_dmu_s_per_region = nullptr;
  const std::uint8_t* transmittance_group = nullptr;
  double* path_scratch = nullptr;
  std::int32_t regions = 0;
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

// Natural logarithm of x in (0, 1], inline: a libm call would make the compiler spill every
// live vector register of the packets in flight around it. Reduction x = 2^k (1 + f) with
// sqrt(1/2) <= 1 + f < sqrt(2), then log(1 + f) = 2 atanh(s), s = f / (2 + f), with the
// classic minimax series in s^2 (as in fdlibm's e_log.c): error below 1 ulp.
[[gnu::always_inline]] inline double log_unit(double x) {
  std::uint64_t bits;
  __builtin_memcpy(&bits, &x, sizeof bits);
  // Subtracting the bits of sqrt(1/2) puts the mantissa cut at sqrt(1/2) instead of 1.
  const std::uint64_t shifted = bits - 0x3fe6a09e667f3bcdull;
  const std::int64_t k = static_cast<std::int64_t>(shifted) >> 52;  // arithmetic shift
  const std::uint64_t mbits = bits - (static_cast<std::uint64_t>(k) << 52);
  double m;
  __builtin_memcpy(&m, &mbits, sizeof m);
  const double f = m - 1.0;
  const double s = f / (2.0 + f);
  const double z = s * s, w = z * z;
  const double t1 =
      w * (3.999999999940941908e-01 + w * (2.222219843214978396e-01 + w * 1.531383769920937332e-01));
  const double t2 =
      z * (6.666666666666735130e-01 +
           w * (2.857142874366239149e-01 + w * (1.818357216161805012e-01 + w * 1.479819860511658591e-01)));
  const double r = t2 + t1;
  const double hfsq = 0.5 * f * f;
  const double dk = static_cast<double>(k);
  return dk * 6.93147180369123816490e-01 - ((hfsq - (s * (hfsq + r) + dk * 1.90821492927058770002e-10)) - f);
}

inline void refract(double* u, const double* m, double eta, double cos_i, double cos_t) {
  // m: unit normal towards the transmission side, u . m = cos_i > 0.
  const double k = cos_t - eta * cos_i;
  for (int c = 0; c < 3; ++c) u[c] = eta * u[c] + k * m[c];
}

// Henyey-Greenstein deflection of u (the polar angle as in MCML, Wang et al. 1995).
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
  const double s_cos = st * (x * x - y * y) * inv_r2, s_sin = st * 2.0 * x * y * inv_r2;
  // Rotate into the frame of u with an orthonormal basis (b1, b2, u) built without a square
  // root or a pole branch (Duff et al. 2017, "Building an orthonormal basis, revisited"):
  // the chain from the old direction to the new one, which every next step waits on, is one
  // division and a few multiply-adds.
  const double ux = u[0], uy = u[1], uz = u[2];
  const double sign = std::copysign(1.0, uz);
  const double a = -1.0 / (sign + uz);
  const double b = ux * uy * a;
  u[0] = s_cos * (1.0 + sign * ux * ux * a) + s_sin * b + ct * ux;
  u[1] = s_cos * (sign * b) + s_sin * (sign + uy * uy * a) + ct * uy;
  u[2] = -(s_cos * sign * ux + s_sin * uy) + ct * uz;
}

}  // namespace detail

/// Packets each thread keeps in flight (see transport_batch). Two give +15 % photons/s over
/// one on the skin slab benchmark; three or four add nothing measurable.
inline constexpr int kPacketsInFlight = 2;

/// What a packet records for the transmittance derivatives: per region slot, the path length
/// travelled (mm) and the number of interactions (scattering events). Empty when the run
/// does not ask for derivatives, so the plain kernel carries nothing extra.
template <bool kRecordPaths>
struct PathRecord {
  double* length;
  double* scatters;
};
template <>
struct PathRecord<false> {};

/// One packet in flight.
template <bool kRecordPaths = false>
struct Packet {
  double p[3], u[3];  // kernel coordinates; unit direction
  double w;           // weight
  double tau;         // optical depth left to the next interaction
  std::int32_t tet;
  std::uint64_t steps;
  PhotonRng rng;
  [[no_unique_address]] PathRecord<kRecordPaths> path;
};

namespace detail {

/// One batch's transport (transport_batch below): the kernel's data, the batch's running
/// tallies and the steps of a packet's life as methods. Every method is always inlined into
/// run(), and the object lives on the caller's stack without its address escaping, so the
/// compiler keeps the running tallies in registers as it did for the locals of one function:
/// it cannot do so for the tally's own fields across stores through the tally's arrays.
template <bool kDerivatives>
class BatchTransport {
 public:
  using Packet = mc::Packet<kDerivatives>;

  TOCD_MC_INLINE BatchTransport(const KernelTet* tets, const KernelLink* links, const KernelOptics* optics,
                                const KernelSettings& s, BatchTally& tally)
      : tets_(tets),
        links_(links),
        optics_(optics),
        s_(s),
        tally_(tally),
        absorbed_per_tet_(tally.absorbed_per_tet),
        absorbed_per_region_(tally.absorbed_per_region),
        exit_per_group_(tally.exit_per_group),
        regions_(tally.regions) {}

  /// Packets in flight, advanced in turn one step each, each relaunched from next_photon when
  /// it ends, until the batch has no photons left; then the running tallies go to the tally.
  template <class NextPhoton>
  TOCD_MC_INLINE void run(NextPhoton& next_photon) {
    Entry entry;
    // Seeds the slot with photons until one enters the mesh; false when the batch is used up.
    auto launch = [&](Packet& ph) TOCD_MC_INLINE {
      while (next_photon(ph.rng, entry)) {
        if (enter(ph, entry)) return true;
      }
      return false;
    };
    Packet packet[kPacketsInFlight];
    bool live[kPacketsInFlight];
    bool any = false;
    if constexpr (kDerivatives) {
      for (int i = 0; i < kPacketsInFlight; ++i) {
        packet[i].path.length = tally_.path_scratch + 2 * i * regions_;
        packet[i].path.scatters = packet[i].path.length + regions_;
      }
    }
    for (int i = 0; i < kPacketsInFlight; ++i) {
      live[i] = launch(packet[i]);
      any = any || live[i];
    }
    while (any) {
      any = false;
#pragma GCC unroll 8
      for (int i = 0; i < kPacketsInFlight; ++i) {
        if (live[i] && !step(packet[i])) live[i] = launch(packet[i]);
        any = any || live[i];
      }
    }
    tally_.roulette += roulette_;
    tally_.lost += lost_;
    tally_.specular += specular_;
    tally_.missed += missed_;
    tally_.events += events_;
    tally_.face_hits += face_hits_;
  }

 private:
  // Perturbation Monte Carlo of the transmittance. The kernel weights by the albedo: free
  // paths are sampled with mu_t (density mu_t^k_r exp(-mu_t L_r) for k_r interactions and
  // path length L_r in region r), and each interaction keeps the fraction mu_s/mu_t of the
  // weight. The product weight x density of an exiting history is thus
  //   prod_r mu_s,r^k_r exp(-(mu_a,r + mu_s,r) L_r) x (factors free of mu_a and mu_s),
  // and reweighting the same history to other coefficients multiplies its weight by the
  // ratio of those products. Its derivative at the sampled coefficients is the score
  //   dw/dmu_a,r = -w L_r,   dw/dmu_s,r = w (k_r / mu_s,r - L_r).
  // Ballistic regions absorb continuously (w *= exp(-mu_a L) along the straight flight) and
  // do not scatter at all, so their weight depends on mu_a alone: dw/dmu_a = -w L_r and
  // dw/dmu_s = 0 (the model neglects their scattering). Fresnel splits, the entry and the
  // phase function do not depend on mu_a or mu_s; roulette keeps the expected weight for any
  // weight, so the scores stay unbiased with it.
  TOCD_MC_INLINE void score_derivatives(const Packet& ph) {
    if constexpr (kDerivatives) {
      for (std::int32_t r = 0; r < regions_; ++r) {
        const double len = ph.path.length[r];
        if (len == 0.0) continue;  // never entered the region
        tally_.dT_dmu_a_per_region[r] -= ph.w * len;
        const KernelOptics& o = optics_[r];
        if (!o.ballistic && o.mu_s > 0.0)
          tally_.dT_dmu_s_per_region[r] += ph.w * (ph.path.scatters[r] / o.mu_s - len);
      }
    }
  }

  TOCD_MC_INLINE void deposit(std::int32_t t, std::int32_t slot, double dep) {
    if (absorbed_per_tet_) absorbed_per_tet_[t] += dep;
    absorbed_per_region_[slot] += dep;
  }
  TOCD_MC_INLINE void enter_tet(std::int32_t t) {
    prefetch_neighbours(tets_, links_, links_[t]);
    if (absorbed_per_tet_) __builtin_prefetch(absorbed_per_tet_ + t, 1);  // the next deposit goes here
  }

  // Entry through the ambient/mesh interface: deterministic specular split. Returns false
  // when the packet never enters.
  TOCD_MC_INLINE bool enter(Packet& ph, const Entry& entry) {
    if (entry.tet < 0) {
      missed_ += 1.0;
      return false;
    }
    ph.w = 1.0;
    for (int c = 0; c < 3; ++c) {
      ph.p[c] = entry.pos[c] - s_.origin[c];
      ph.u[c] = entry.dir[c];
    }
    ph.tet = entry.tet;
    ph.steps = 0;
    const KernelTet& k = tets_[ph.tet];
    const int f = entry.face;
    const double m[3] = {-k.nx[f], -k.ny[f], -k.nz[f]};
    const double cos_i = ph.u[0] * m[0] + ph.u[1] * m[1] + ph.u[2] * m[2];
    const double n2 = optics_[links_[ph.tet].region_slot].n;
    double cos_t;
    const double r = fresnel_reflectance(s_.ambient_n, n2, cos_i, cos_t);
    if (r >= 1.0) {  // cannot enter at all (denser ambient beyond the critical angle)
      specular_ += 1.0;
      return false;
    }
    if (s_.entry_specular) {
      specular_ += r;
      ph.w = 1.0 - r;
    }
    if (s_.ambient_n != n2) refract(ph.u, m, s_.ambient_n / n2, cos_i, cos_t);
    enter_tet(ph.tet);
    if constexpr (kDerivatives) {
      for (std::int32_t q = 0; q < regions_; ++q) ph.path.length[q] = ph.path.scatters[q] = 0.0;
    }
    ph.tau = -log_unit(ph.rng.uniform());
    return true;
  }

  // Russian roulette for a light packet: survive 1 in `chance` with `chance` times the
  // weight, so the expected weight is unchanged. Returns false when the packet died.
  TOCD_MC_INLINE bool survives_roulette(Packet& ph) {
    if (ph.w >= s_.roulette_threshold) return true;
    if (ph.rng.uniform() * s_.roulette_chance < 1.0) {
      roulette_ -= ph.w * (s_.roulette_chance - 1.0);
      ph.w *= s_.roulette_chance;
      return true;
    }
    roulette_ += ph.w;
    return false;
  }

  // An interaction at distance `dist` inside the current tet: move, deposit the absorbed
  // fraction (implicit capture), deflect, play roulette, draw the next optical depth.
  // Returns false when the packet died in roulette.
  TOCD_MC_INLINE bool interact(Packet& ph, const KernelLink& k, const KernelOptics& o, double dist) {
    for (int c = 0; c < 3; ++c) ph.p[c] += dist * ph.u[c];
    if constexpr (kDerivatives) {
      ph.path.length[k.region_slot] += dist;
      ph.path.scatters[k.region_slot] += 1.0;
    }
    const double dep = ph.w * o.absorb_fraction;
    deposit(ph.tet, k.region_slot, dep);
    ph.w -= dep;
    ++events_;
    scatter(ph.u, o, ph.rng);
    if (!survives_roulette(ph)) return false;
    ph.tau = -log_unit(ph.rng.uniform());
    return true;
  }

  // One step of a packet: an interaction inside its tet, or a move to the nearest face and
  // the crossing of (or reflection off) it. Returns false when the packet ended.
  TOCD_MC_INLINE bool step(Packet& ph) {
    if (++ph.steps > s_.max_steps) {
      lost_ += ph.w;
      return false;
    }
    const KernelTet& k = tets_[ph.tet];
    const KernelLink& link = links_[ph.tet];
    const KernelOptics& o = optics_[link.region_slot];
    const double* const p = ph.p;
    const double* const u = ph.u;
    // cos of the direction with each outward normal, and distance of p inside each plane, for
    // the four faces at once (one vector lane per face).
    const Lanes4 nx = widen(k.nx), ny = widen(k.ny), nz = widen(k.nz);
    const Lanes4 cosf = nx * u[0] + ny * u[1] + nz * u[2];
    const Lanes4 gap = widen(k.offset) - (nx * p[0] + ny * p[1] + nz * p[2]);

    // Fast path, taken by most steps in scattering tissue: the next interaction point
    // p + s u lies inside this tet iff it is inside all four planes. Four multiply-adds and a
    // min, no division and no data-dependent branch per face.
    const double to_event = o.ballistic ? HUGE_VAL : ph.tau * o.inv_mu_t;
    if (!o.ballistic) {
      if (min_lane(gap - to_event * cosf) >= 0.0) return interact(ph, link, o, to_event);
    }

    // Slow path: the nearest face the packet moves towards. Slightly negative distances
    // (round-off puts p a hair outside a plane) are clamped to 0.
    // Written as selects, not branches: which face wins is unpredictable.
    const Lanes4 q = gap / cosf;
    const Lanes4 zero = {0.0, 0.0, 0.0, 0.0}, never = {HUGE_VAL, HUGE_VAL, HUGE_VAL, HUGE_VAL};
    const Lanes4 d = cosf > zero ? (q > zero ? q : zero) : never;
    const int f01 = d[1] < d[0] ? 1 : 0, f23 = d[3] < d[2] ? 3 : 2;
    const int face = d[f23] < d[f01] ? f23 : f01;
    const double best = d[face];
    if (best == HUGE_VAL) {  // zero direction: cannot happen for unit u, but never loop
      lost_ += ph.w;
      return false;
    }
    if (to_event < best) return interact(ph, link, o, to_event);  // round-off corner: inside after all
    if constexpr (kDerivatives) ph.path.length[link.region_slot] += best;
    if (o.ballistic) {
      const double dep = ph.w * (1.0 - std::exp(-o.mu_a * best));
      deposit(ph.tet, link.region_slot, dep);
      ph.w -= dep;
      // Also here: a packet trapped by total internal reflection in weakly absorbing glass
      // would otherwise bounce until the step guard.
      if (!survives_roulette(ph)) return false;
    } else {
      ph.tau -= best * o.mu_t;
    }
    return cross_face(ph, k, link, o, face, cosf[face], best);
  }

  // Moves the packet `best` to the face and crosses it, or reflects off it (Fresnel). Returns
  // false when the packet left the mesh.
  TOCD_MC_INLINE bool cross_face(Packet& ph, const KernelTet& k, const KernelLink& link,
                                 const KernelOptics& o, int face, double cos_i, double best) {
    double* const p = ph.p;
    double* const u = ph.u;
    ++face_hits_;
    for (int c = 0; c < 3; ++c) p[c] += best * u[c];
    const std::int32_t next = link.next[face];
    const double n1 = o.n;
    const double n2 = next >= 0 ? optics_[link.next_slot[face]].n : s_.ambient_n;
    if (n1 != n2) {
      const double m[3] = {k.nx[face], k.ny[face], k.nz[face]};
      double cos_t;
      const double r = fresnel_reflectance(n1, n2, cos_i, cos_t);
      if (r >= 1.0 || ph.rng.uniform() < r) {
        for (int c = 0; c < 3; ++c) u[c] -= 2.0 * cos_i * m[c];
        return true;
      }
      refract(u, m, n1 / n2, cos_i, cos_t);
    }
    if (next < 0) {
      exit_per_group_[-1 - next] += ph.w;
      if constexpr (kDerivatives) {
        if (tally_.transmittance_group[-1 - next]) score_derivatives(ph);
      }
      return false;
    }
    ph.tet = next;
    enter_tet(next);
    return true;
  }

  const KernelTet* const tets_;
  const KernelLink* const links_;
  const KernelOptics* const optics_;
  const KernelSettings& s_;
  BatchTally& tally_;
  double* const absorbed_per_tet_;
  double* const absorbed_per_region_;
  double* const exit_per_group_;
  const std::int32_t regions_;
  double roulette_ = 0.0, lost_ = 0.0, specular_ = 0.0, missed_ = 0.0;
  std::uint64_t events_ = 0, face_hits_ = 0;
};

}  // namespace detail

/// Transports the packets of one batch from entry to termination (leaving the mesh, dying in
/// roulette or hitting the step guard); every bit of weight ends in exactly one tally.
/// `next_photon(PhotonRng&, Entry&)` seeds the next photon's stream and samples its entry;
/// it returns false when the batch has no photons left.
///
/// Two packets are in flight at once and advance in turn, one step each. A single packet's
/// steps form one long dependency chain (direction -> face test -> branch -> next
/// direction) that leaves most of the core idle; a second, independent chain fills it. The
/// order of packets and of their random draws depends only on the batch, never on the thread
/// that runs it, so results stay bitwise reproducible.
/// Always inlined: its caller has ISA versions (run_batch, tocd/core/isa_dispatch.hpp), and
/// each must hold the whole loop; left to the inliner, three callers make it too big to
/// inline and every version would call one baseline copy.
///
/// kDerivatives: each packet also records its path length and interactions per region, and a
/// packet leaving through a transmittance face scores the derivatives of its weight (see
/// BatchTransport::score_derivatives). No random draw depends on it: the histories, and every
/// other tally, are bitwise those of the plain kernel.
template <bool kDerivatives = false, class NextPhoton>
TOCD_MC_INLINE inline void transport_batch(const KernelTet* tets, const KernelLink* links,
                                           const KernelOptics* optics, const KernelSettings& s,
                                           BatchTally& tally, NextPhoton&& next_photon) {
  detail::BatchTransport<kDerivatives> transport(tets, links, optics, s, tally);
  transport.run(next_photon);
}

}  // namespace tocd::sim::mc
