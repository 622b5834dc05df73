#pragma once

#include <cstdint>

#include <Random123/philox.h>

namespace tocd::sim::mc {

/// One xoshiro128++ step on the state words s[0..3]: returns the draw and advances the state.
/// W is a 32-bit word, or a vector of them for the kernel's lanes (lanes.hpp), which thus draw
/// bit for bit what PhotonRng draws.
template <class W>
[[gnu::always_inline]] inline W xoshiro128pp_next(W (&s)[4]) noexcept {
  const auto rotl = [](W x, int k) { return (x << k) | (x >> (32 - k)); };
  const W result = rotl(s[0] + s[3], 7) + s[0];
  const W t = s[1] << 9;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rotl(s[3], 11);
  return result;
}

/// The random stream of one photon. Philox4x32-10, keyed by the run seed with the photon
/// index as counter, gives 128 bits that seed a xoshiro128++ generator for that photon alone.
/// Any photon's stream is a function of (seed, photon index) only, so results do not depend on
/// which thread ran which photon; within the photon, xoshiro128++ costs a handful of integer
/// operations per draw and has no buffer whose refill would be a branch in the kernel.
/// (xoshiro128++ passes BigCrush; streams start at independent uniformly random points of its
/// 2^128 - 1 period, so two photons' streams overlapping is out of reach.)
class PhotonRng {
 public:
  PhotonRng() noexcept = default;
  PhotonRng(std::uint64_t seed, std::uint64_t photon) noexcept {
    const r123::Philox4x32::key_type key = {
        {static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)}};
    const r123::Philox4x32::ctr_type ctr = {
        {static_cast<std::uint32_t>(photon), static_cast<std::uint32_t>(photon >> 32), 0u, 0u}};
    const r123::Philox4x32::ctr_type b = r123::Philox4x32()(ctr, key);
    for (int i = 0; i < 4; ++i) s_[i] = b.v[i];
    if ((s_[0] | s_[1] | s_[2] | s_[3]) == 0u) s_[0] = 1u;  // the one state xoshiro cannot leave
  }

  /// The generator in the state (a, b, c, d), as state(0..3) reads it back (the kernel keeps
  /// the streams of its vector lanes in that form).
  static PhotonRng from_state(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) noexcept {
    PhotonRng r;
    r.s_[0] = a;
    r.s_[1] = b;
    r.s_[2] = c;
    r.s_[3] = d;
    return r;
  }
  std::uint32_t state(int k) const noexcept { return s_[k]; }

  /// One raw 32-bit draw.
  [[gnu::always_inline]] std::uint32_t bits() noexcept { return xoshiro128pp_next(s_); }

  /// Uniform in the open interval (0, 1): (k + 0.5) / 2^32, never 0 so log() is safe.
  [[gnu::always_inline]] double uniform() noexcept {
    return (static_cast<double>(bits()) + 0.5) * (1.0 / 4294967296.0);
  }

 private:
  std::uint32_t s_[4] = {1u, 0u, 0u, 0u};
};

}  // namespace tocd::sim::mc
