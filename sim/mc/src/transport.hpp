#pragma once
// The photon transport kernel: packets from entry to termination. Plain data in, tallies
// out; no virtual calls, no allocation, no exceptions, so it can be ported to a GPU as is.

#include <cmath>
#include <cstdint>
#include <numbers>

#include "lanes.hpp"
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

}  // namespace detail

/// Packets each thread keeps in flight: one per vector lane (see transport_batch).
inline constexpr int kPacketsInFlight = lanes::kLanes;

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

/// One packet, as the kernel's scalar parts (entry, crossings of an index change, exits) see
/// the packet of one lane.
template <bool kRecordPaths = false>
struct Packet {
  double p[3], u[3];  // kernel coordinates; unit direction
  double w;           // weight
  double tau;         // optical depth left to the next interaction
  std::int32_t tet;
  PhotonRng rng;
  [[no_unique_address]] PathRecord<kRecordPaths> path;
};

namespace detail {

/// One batch's transport (transport_batch below): the kernel's data, the packets of the eight
/// lanes and the batch's running tallies, with the steps of a packet's life as methods. Every
/// method is always inlined into run(), and the object lives on the caller's stack without its
/// address escaping.
///
/// A step is taken by all lanes at once: the face tests, the choice between an interaction and
/// a crossing, the move, the deflection and the next free path are vector arithmetic with the
/// outcome of each lane selected by masks, so no lane's outcome is a branch. What is rare or
/// touches memory per lane runs lane by lane: the per-tet deposits, roulette, moving into the
/// next tet, crossings where the refractive index changes, exits and relaunches.
template <bool kDerivatives>
class BatchTransport {
 public:
  using Packet = mc::Packet<kDerivatives>;
  using D8 = lanes::D8;
  using M8 = lanes::M8;
  static constexpr int kLanes = lanes::kLanes;

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

  /// Fills the lanes from next_photon and steps them all until the batch has no photons left;
  /// a lane whose packet ends takes the batch's next photon. Then the running tallies go to
  /// the tally.
  template <class NextPhoton>
  TOCD_MC_INLINE void run(NextPhoton& next_photon) {
    Entry entry;
    if constexpr (kDerivatives) {
      for (int i = 0; i < kLanes; ++i) {
        path_[i].length = tally_.path_scratch + 2 * i * regions_;
        path_[i].scatters = path_[i].length + regions_;
      }
    }
    for (int i = 0; i < kLanes; ++i) launch(i, next_photon, entry);
    while (live_ != 0) {
      const unsigned ended = step();
      for (unsigned e = ended; e != 0; e &= e - 1) launch(__builtin_ctz(e), next_photon, entry);
    }
    for (int i = 0; i < kLanes; ++i) flush_region(i);
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

  // A deposit outside the vector arithmetic (ballistic flights).
  TOCD_MC_INLINE void deposit(int lane, double dep) {
    if (absorbed_per_tet_) absorbed_per_tet_[tet_[lane]] += dep;
    absorbed_region_[lane] += dep;
  }
  // Lane i's deposits in its region since it entered it go to the region's tally. Summed per
  // lane first: eight lanes adding into one region's total in turn would wait on each other.
  TOCD_MC_INLINE void flush_region(int i) {
    if (slot_[i] >= 0) absorbed_per_region_[slot_[i]] += absorbed_region_[i];
    absorbed_region_[i] = 0.0;
  }

  // The packet of lane i as one packet, and back.
  TOCD_MC_INLINE Packet packet_of(int i) const {
    Packet ph;
    ph.p[0] = px_[i], ph.p[1] = py_[i], ph.p[2] = pz_[i];
    ph.u[0] = ux_[i], ph.u[1] = uy_[i], ph.u[2] = uz_[i];
    ph.w = w_[i];
    ph.tau = tau_[i];
    ph.tet = tet_[i];
    ph.rng = rng_.lane(i);
    if constexpr (kDerivatives) ph.path = path_[i];
    return ph;
  }
  TOCD_MC_INLINE void put(int i, const Packet& ph) {
    px_[i] = ph.p[0], py_[i] = ph.p[1], pz_[i] = ph.p[2];
    ux_[i] = ph.u[0], uy_[i] = ph.u[1], uz_[i] = ph.u[2];
    w_[i] = ph.w;
    tau_[i] = ph.tau;
    rng_.set(i, ph.rng);
  }

  // Lane i moves into tet t: its region's optics when the region changes, and the records of
  // its four neighbours and its tally slot fetched ahead (the next tet is one of those
  // neighbours; on meshes larger than the cache the crossing would otherwise wait on memory).
  TOCD_MC_INLINE void enter_tet(int i, std::int32_t t) {
    tet_[i] = t;
    const KernelLink& link = links_[t];
    prefetch_neighbours(tets_, links_, link);
    if (absorbed_per_tet_) __builtin_prefetch(absorbed_per_tet_ + t, 1);  // the next deposit goes here
    if (link.region_slot != slot_[i]) {
      flush_region(i);
      const KernelOptics& o = optics_[link.region_slot];
      slot_[i] = link.region_slot;
      mu_t_[i] = o.mu_t;
      inv_mu_t_[i] = o.inv_mu_t;
      absorb_fraction_[i] = o.absorb_fraction;
      n_[i] = o.n;
      hg_one_minus_g2_[i] = o.hg_one_minus_g2;
      hg_one_plus_g2_[i] = o.hg_one_plus_g2;
      hg_one_minus_g_[i] = o.hg_one_minus_g;
      hg_two_g_[i] = o.hg_two_g;
      hg_inv_two_g_[i] = o.hg_inv_two_g;
      isotropic_[i] = o.g == 0.0 ? -1 : 0;
      ballistic_[i] = o.ballistic ? -1 : 0;
    }
  }

  // Seeds lane i with photons from next_photon until one enters the mesh; the lane goes idle
  // when the batch is used up.
  template <class NextPhoton>
  TOCD_MC_INLINE void launch(int i, NextPhoton& next_photon, Entry& entry) {
    Packet ph;
    if constexpr (kDerivatives) ph.path = path_[i];
    while (next_photon(ph.rng, entry)) {
      if (enter(ph, entry)) {
        put(i, ph);
        steps_[i] = 0;
        enter_tet(i, ph.tet);
        live_ |= 1u << i;
        return;
      }
    }
    live_ &= ~(1u << i);
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
    if constexpr (kDerivatives) {
      for (std::int32_t q = 0; q < regions_; ++q) ph.path.length[q] = ph.path.scatters[q] = 0.0;
    }
    ph.tau = -lanes::log_unit(ph.rng.uniform());
    return true;
  }

  // Russian roulette for a light packet: survive 1 in `chance` with `chance` times the
  // weight, so the expected weight is unchanged. Returns false when the packet died.
  TOCD_MC_INLINE bool survives_roulette(double& w, PhotonRng& rng) {
    if (w >= s_.roulette_threshold) return true;
    if (rng.uniform() * s_.roulette_chance < 1.0) {
      roulette_ -= w * (s_.roulette_chance - 1.0);
      w *= s_.roulette_chance;
      return true;
    }
    roulette_ += w;
    return false;
  }

  // survives_roulette for the packet of lane i.
  TOCD_MC_INLINE bool lane_survives_roulette(int i) {
    PhotonRng rng = rng_.lane(i);
    double w = w_[i];
    const bool survives = survives_roulette(w, rng);
    w_[i] = w;
    rng_.set(i, rng);
    return survives;
  }

  // One step of every live lane: an interaction inside its tet, or a move to the nearest face
  // and the crossing of (or reflection off) it. Returns the lanes whose packets ended.
  TOCD_MC_INLINE unsigned step() {
    unsigned ended = 0;
    // Guard against a packet that stops making progress.
    steps_ += lanes::mask_of(live_) & 1;
    const unsigned stuck = live_ & lanes::bits_of(steps_ > static_cast<std::int64_t>(s_.max_steps));
    for (unsigned e = stuck; e != 0; e &= e - 1) lost_ += w_[__builtin_ctz(e)];
    ended |= stuck;
    const unsigned active = live_ & ~stuck;

    // The planes of each lane's tet (column 4q + f: normal x, y, z and offset, q = 0..3, of
    // face f), then the cos of the direction with each outward normal and the distance of p
    // inside each plane.
    lanes::F16 records[kLanes];
    for (int i = 0; i < kLanes; ++i) __builtin_memcpy(&records[i], &tets_[tet_[i]], sizeof records[i]);
    D8 plane[16];
    lanes::transpose(records, plane);
    D8 cosf[4], gap[4];
    for (int f = 0; f < 4; ++f) {
      const D8 nx = plane[f], ny = plane[4 + f], nz = plane[8 + f];
      cosf[f] = nx * ux_ + ny * uy_ + nz * uz_;
      gap[f] = plane[12 + f] - (nx * px_ + ny * py_ + nz * pz_);
    }
    // The next interaction point p + s u lies inside the tet iff it is inside all four planes.
    // Ballistic lanes have no interaction ahead.
    const D8 to_event = lanes::select(ballistic_, lanes::splat(HUGE_VAL), tau_ * inv_mu_t_);
    D8 slack = gap[0] - to_event * cosf[0];
    for (int f = 1; f < 4; ++f) slack = lanes::min(slack, gap[f] - to_event * cosf[f]);
    // The nearest face the packet moves towards (the first of equal ones). Slightly negative
    // distances (round-off puts p a hair outside a plane) are clamped to 0.
    D8 best = lanes::splat(HUGE_VAL);
    M8 face = M8{};
    for (int f = 0; f < 4; ++f) {
      const D8 q = gap[f] / cosf[f];
      const D8 d = cosf[f] > 0.0 ? (q > 0.0 ? q : D8{}) : lanes::splat(HUGE_VAL);
      const M8 nearer = d < best;
      best = lanes::select(nearer, d, best);
      face = nearer ? M8{} + f : face;
    }
    // Inside after all when the interaction comes before the nearest face (a round-off corner).
    // Never in a ballistic lane, whose slack may come out of the min as +inf.
    const unsigned event = active & lanes::bits_of(((slack >= 0.0) | (to_event < best)) & ~ballistic_);
    unsigned cross = active & ~event;
    const unsigned lost = cross & lanes::bits_of(best == HUGE_VAL);  // zero direction: never loop
    for (unsigned e = lost; e != 0; e &= e - 1) lost_ += w_[__builtin_ctz(e)];
    ended |= lost;
    cross &= ~lost;

    const M8 moving = lanes::mask_of(event | cross);
    const M8 event_m = lanes::mask_of(event);
    const D8 dist = lanes::select(event_m, to_event, best);
    px_ = lanes::select(moving, px_ + dist * ux_, px_);
    py_ = lanes::select(moving, py_ + dist * uy_, py_);
    pz_ = lanes::select(moving, pz_ + dist * uz_, pz_);
    if (event != 0) ended |= interact(event, event_m, dist);
    if (cross != 0) ended |= cross_faces(cross, best, face, cosf);
    return ended;
  }

  // The lanes in `event` interact at distance `dist`: deposit the absorbed fraction (implicit
  // capture), deflect, play roulette, draw the next optical depth. Returns the lanes that died
  // in roulette.
  TOCD_MC_INLINE unsigned interact(unsigned event, M8 event_m, D8 dist) {
    const D8 dep = w_ * absorb_fraction_;
    if (absorbed_per_tet_) {
      for (unsigned e = event; e != 0; e &= e - 1) {
        const int i = __builtin_ctz(e);
        absorbed_per_tet_[tet_[i]] += dep[i];
      }
    }
    if constexpr (kDerivatives) {
      for (unsigned e = event; e != 0; e &= e - 1) {
        const int i = __builtin_ctz(e);
        path_[i].length[slot_[i]] += dist[i];
        path_[i].scatters[slot_[i]] += 1.0;
      }
    }
    absorbed_region_ = lanes::select(event_m, absorbed_region_ + dep, absorbed_region_);
    w_ = lanes::select(event_m, w_ - dep, w_);
    events_ += static_cast<unsigned>(__builtin_popcount(event));
    scatter(event_m);
    unsigned died = 0;
    const unsigned light = event & lanes::bits_of(w_ < s_.roulette_threshold);
    for (unsigned e = light; e != 0; e &= e - 1) {
      const int i = __builtin_ctz(e);
      if (!lane_survives_roulette(i)) died |= 1u << i;
    }
    const M8 flying = lanes::mask_of(event & ~died);
    tau_ = lanes::select(flying, -lanes::log_unit(rng_.uniform(flying)), tau_);
    return died;
  }

  // Henyey-Greenstein deflection of the lanes in m: the polar angle as in MCML (Wang et al.
  // 1995); the azimuth without trigonometry, from a uniform point (x, y) in the unit disk
  // (cos = (x^2 - y^2) / r^2, sin = 2xy / r^2; x and y take 16 bits each of one draw; r^2 < 1e-4
  // is rejected too), a lane whose point falls outside drawing again while the others wait;
  // the rotation into the frame of the old direction with an orthonormal basis built without
  // a square root or a pole branch (Duff et al. 2017).
  TOCD_MC_INLINE void scatter(M8 m) {
    const D8 xi = rng_.uniform(m);
    const D8 tmp = hg_one_minus_g2_ / (hg_one_minus_g_ + hg_two_g_ * xi);
    D8 ct = (hg_one_plus_g2_ - tmp * tmp) * hg_inv_two_g_;
    ct = ct < -1.0 ? lanes::splat(-1.0) : (ct > 1.0 ? lanes::splat(1.0) : ct);
    ct = lanes::select(isotropic_, 2.0 * xi - 1.0, ct);
    const D8 st = lanes::sqrt(1.0 - ct * ct);
    D8 x = lanes::splat(1.0), y = D8{}, r2 = lanes::splat(1.0);
    M8 pending = m;
    do {
      const lanes::U8 b = rng_.bits(pending);
      const D8 xs = (__builtin_convertvector(b & 0xffffu, D8) + 0.5) * (2.0 / 65536.0) - 1.0;
      const D8 ys = (__builtin_convertvector(b >> 16, D8) + 0.5) * (2.0 / 65536.0) - 1.0;
      const D8 rs = xs * xs + ys * ys;
      x = lanes::select(pending, xs, x);
      y = lanes::select(pending, ys, y);
      r2 = lanes::select(pending, rs, r2);
      pending &= (rs > 1.0) | (rs < 1e-4);
    } while (lanes::bits_of(pending) != 0);
    const D8 inv_r2 = 1.0 / r2;
    const D8 s_cos = st * (x * x - y * y) * inv_r2, s_sin = st * 2.0 * x * y * inv_r2;
    const D8 ux = ux_, uy = uy_, uz = uz_;
    const D8 sign = lanes::copysign_one(uz);
    const D8 a = -1.0 / (sign + uz);
    const D8 b = ux * uy * a;
    ux_ = lanes::select(m, s_cos * (1.0 + sign * ux * ux * a) + s_sin * b + ct * ux, ux);
    uy_ = lanes::select(m, s_cos * (sign * b) + s_sin * (sign + uy * uy * a) + ct * uy, uy);
    uz_ = lanes::select(m, -(s_cos * sign * ux + s_sin * uy) + ct * uz, uz);
  }

  // The lanes in `cross` have moved `best` to face `face` of their tet: each crosses it, or
  // reflects off it (Fresnel). Ballistic lanes first absorb along the flight. Returns the
  // lanes whose packets ended (left the mesh or died in roulette).
  TOCD_MC_INLINE unsigned cross_faces(unsigned cross, D8 best, M8 face, const D8* cosf) {
    tau_ = lanes::select(lanes::mask_of(cross) & ~ballistic_, tau_ - best * mu_t_, tau_);
    unsigned ended = 0;
    for (unsigned e = cross; e != 0; e &= e - 1) {
      const int i = __builtin_ctz(e);
      if constexpr (kDerivatives) path_[i].length[slot_[i]] += best[i];
      if (ballistic_[i]) {
        const double dep = w_[i] * (1.0 - std::exp(-optics_[slot_[i]].mu_a * best[i]));
        deposit(i, dep);
        w_[i] -= dep;
        // Also here: a packet trapped by total internal reflection in weakly absorbing glass
        // would otherwise bounce until the step guard.
        if (!lane_survives_roulette(i)) {
          ended |= 1u << i;
          continue;
        }
      }
      ++face_hits_;
      const int f = static_cast<int>(face[i]);
      const KernelLink& link = links_[tet_[i]];
      const std::int32_t next = link.next[f];
      if (next >= 0 && optics_[link.next_slot[f]].n == n_[i]) {  // the common case: on into the next tet
        enter_tet(i, next);
        continue;
      }
      Packet ph = packet_of(i);
      if (!cross_face(ph, link, f, cosf[f][i], i)) {
        ended |= 1u << i;
        continue;
      }
      put(i, ph);
      if (ph.tet != tet_[i]) enter_tet(i, ph.tet);
    }
    return ended;
  }

  // Crossing of a face where the refractive index changes or the mesh ends: the Fresnel
  // split, then the next tet or the exit. Returns false when the packet left the mesh.
  TOCD_MC_INLINE bool cross_face(Packet& ph, const KernelLink& link, int face, double cos_i, int lane) {
    double* const u = ph.u;
    const std::int32_t next = link.next[face];
    const double n1 = n_[lane];
    const double n2 = next >= 0 ? optics_[link.next_slot[face]].n : s_.ambient_n;
    if (n1 != n2) {
      const KernelTet& k = tets_[ph.tet];
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

  // The packets of the lanes: position (kernel coordinates), unit direction, weight, optical
  // depth left to the next interaction, steps taken, random stream, tet.
  D8 px_{}, py_{}, pz_{}, ux_{}, uy_{}, uz_{}, w_{}, tau_{};
  M8 steps_{};
  lanes::Rng rng_{};
  std::int32_t tet_[kLanes] = {};
  unsigned live_ = 0;  // bit i: lane i holds a packet
  // Each lane's region: its optics slot and what the steps need of its optics.
  std::int32_t slot_[kLanes] = {-1, -1, -1, -1, -1, -1, -1, -1};
  D8 mu_t_{}, inv_mu_t_{}, absorb_fraction_{}, n_{};
  D8 absorbed_region_{};  // deposited in the region since the lane entered it
  D8 hg_one_minus_g2_{}, hg_one_plus_g2_{}, hg_one_minus_g_{}, hg_two_g_{}, hg_inv_two_g_{};
  M8 isotropic_{}, ballistic_{};
  [[no_unique_address]] PathRecord<kDerivatives> path_[kLanes];
};

}  // namespace detail

/// Transports the packets of one batch from entry to termination (leaving the mesh, dying in
/// roulette or hitting the step guard); every bit of weight ends in exactly one tally.
/// `next_photon(PhotonRng&, Entry&)` seeds the next photon's stream and samples its entry;
/// it returns false when the batch has no photons left.
///
/// Eight packets are in flight at once, one per vector lane, and step together (see
/// detail::BatchTransport). Each packet draws from its photon's own stream, and ended lanes
/// take the batch's next photons in lane order, so the histories and the order of the
/// tallies' additions depend only on the batch, never on the thread that runs it: results
/// stay bitwise reproducible.
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
