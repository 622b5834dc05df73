#pragma once
// Eight photon packets side by side in vector lanes (GCC/Clang vector extensions): the types,
// the per-lane random streams and the elementary functions the transport kernel needs for all
// lanes at once. Eight lanes on every CPU (one AVX-512 register, two AVX2 ones, four SSE2
// pairs), so the order in which packets end, and with it every tally's rounding, does not
// depend on the instruction set.

#include <cstdint>
#include <type_traits>

#include "photon_rng.hpp"

namespace tocd::sim::mc::lanes {

inline constexpr int kLanes = 8;

using D8 = double __attribute__((vector_size(8 * kLanes)));         // one double per lane
using M8 = std::int64_t __attribute__((vector_size(8 * kLanes)));   // a D8 comparison: -1 or 0
using I8 = std::int32_t __attribute__((vector_size(4 * kLanes)));   // one int per lane
using U8 = std::uint32_t __attribute__((vector_size(4 * kLanes)));  // one 32-bit draw per lane

[[gnu::always_inline]] inline D8 splat(double x) {
  return D8{} + x;
}

using F16 = float __attribute__((vector_size(64)));  // one 64-byte record

/// Column c of the 16-float records in rows[0..7] (record i in lane i), as doubles, for every
/// c: the three rounds of pairwise interleaving of an 8 x 16 transpose, then the widening.
/// Eight vector loads and 24 two-register shuffles where inserting the 128 values lane by lane
/// would take 128 scalar loads.
[[gnu::always_inline]] inline void transpose(const F16 (&rows)[kLanes], D8 (&columns)[16]) {
  F16 a[kLanes], b[kLanes];
  // Pairs of records: a[2k] holds columns 0..7 of records 2k and 2k+1 interleaved, a[2k+1]
  // columns 8..15.
  for (int k = 0; k < 4; ++k) {
    a[2 * k] = __builtin_shufflevector(rows[2 * k], rows[2 * k + 1], 0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21,
                                       6, 22, 7, 23);
    a[2 * k + 1] = __builtin_shufflevector(rows[2 * k], rows[2 * k + 1], 8, 24, 9, 25, 10, 26, 11, 27, 12, 28,
                                           13, 29, 14, 30, 15, 31);
  }
  // Quads of records: b[4h + 2j + s] holds, for records 4h..4h+3, columns 8j + 4s .. 8j + 4s + 3,
  // each as four consecutive lanes.
  for (int h = 0; h < 2; ++h) {
    for (int j = 0; j < 2; ++j) {
      const F16 lo = a[4 * h + j], hi = a[4 * h + 2 + j];
      b[4 * h + 2 * j] =
          __builtin_shufflevector(lo, hi, 0, 1, 16, 17, 2, 3, 18, 19, 4, 5, 20, 21, 6, 7, 22, 23);
      b[4 * h + 2 * j + 1] =
          __builtin_shufflevector(lo, hi, 8, 9, 24, 25, 10, 11, 26, 27, 12, 13, 28, 29, 14, 15, 30, 31);
    }
  }
  // All eight records: two columns of eight lanes per vector.
  for (int q = 0; q < 4; ++q) {
    const F16 lo = b[q], hi = b[4 + q];
    const F16 c01 = __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 16, 17, 18, 19, 4, 5, 6, 7, 20, 21, 22, 23);
    const F16 c23 =
        __builtin_shufflevector(lo, hi, 8, 9, 10, 11, 24, 25, 26, 27, 12, 13, 14, 15, 28, 29, 30, 31);
    // b[q] covers columns 4q .. 4q + 3 (q = 2j + s above).
    columns[4 * q + 0] =
        __builtin_convertvector(__builtin_shufflevector(c01, c01, 0, 1, 2, 3, 4, 5, 6, 7), D8);
    columns[4 * q + 1] =
        __builtin_convertvector(__builtin_shufflevector(c01, c01, 8, 9, 10, 11, 12, 13, 14, 15), D8);
    columns[4 * q + 2] =
        __builtin_convertvector(__builtin_shufflevector(c23, c23, 0, 1, 2, 3, 4, 5, 6, 7), D8);
    columns[4 * q + 3] =
        __builtin_convertvector(__builtin_shufflevector(c23, c23, 8, 9, 10, 11, 12, 13, 14, 15), D8);
  }
}

/// Bit i set where lane i of the comparison is true.
[[gnu::always_inline]] inline unsigned bits_of(M8 m) {
  unsigned b = 0;
  for (int i = 0; i < kLanes; ++i) b |= static_cast<unsigned>(m[i] != 0) << i;
  return b;
}

/// The lanes of a bit set as a comparison mask.
[[gnu::always_inline]] inline M8 mask_of(unsigned b) {
  M8 m;
  for (int i = 0; i < kLanes; ++i) m[i] = -static_cast<std::int64_t>((b >> i) & 1u);
  return m;
}

[[gnu::always_inline]] inline D8 select(M8 m, D8 a, D8 b) {
  return m ? a : b;
}
[[gnu::always_inline]] inline D8 min(D8 a, D8 b) {
  return a < b ? a : b;
}

/// Square root of every lane (one vector instruction where the ISA has it; the kernel is built
/// with -fno-math-errno so no lane needs a libm call).
[[gnu::always_inline]] inline D8 sqrt(D8 x) {
  D8 r;
  for (int i = 0; i < kLanes; ++i) r[i] = __builtin_sqrt(x[i]);
  return r;
}

/// 1 with the sign of x in every lane, as std::copysign(1.0, x).
[[gnu::always_inline]] inline D8 copysign_one(D8 x) {
  const M8 sign = __builtin_bit_cast(M8, x) & static_cast<std::int64_t>(0x8000000000000000ull);
  return __builtin_bit_cast(D8, sign | __builtin_bit_cast(M8, splat(1.0)));
}

/// The xoshiro128++ streams of the packets in the lanes, state word k of lane i in s[k][i]:
/// each lane's draws are bit for bit those its PhotonRng would give.
struct Rng {
  U8 s[4];

  /// Lane i takes the stream `rng`, or gives back its own.
  [[gnu::always_inline]] void set(int i, const PhotonRng& rng) {
    for (int k = 0; k < 4; ++k) s[k][i] = rng.state(k);
  }
  [[gnu::always_inline]] PhotonRng lane(int i) const {
    return PhotonRng::from_state(s[0][i], s[1][i], s[2][i], s[3][i]);
  }

  /// One draw in every lane; the streams of the lanes outside `advance` stay where they were.
  [[gnu::always_inline]] U8 bits(M8 advance) {
    U8 next[4] = {s[0], s[1], s[2], s[3]};
    const U8 result = xoshiro128pp_next(next);
    const I8 keep = __builtin_convertvector(advance, I8) == 0;
    for (int k = 0; k < 4; ++k) s[k] = keep ? s[k] : next[k];
    return result;
  }

  /// Uniform in (0, 1) as PhotonRng::uniform.
  [[gnu::always_inline]] D8 uniform(M8 advance) {
    return (__builtin_convertvector(bits(advance), D8) + 0.5) * (1.0 / 4294967296.0);
  }
};

/// Natural logarithm of x in (0, 1], of one double or in every lane of a D8, inline: a libm
/// call would make the compiler spill every live vector register around it. Reduction
/// x = 2^k (1 + f) with sqrt(1/2) <= 1 + f < sqrt(2), then log(1 + f) = 2 atanh(s),
/// s = f / (2 + f), with the classic minimax series in s^2 (as in fdlibm's e_log.c): error
/// below 1 ulp.
template <class V>
[[gnu::always_inline]] inline V log_unit(V x) {
  constexpr bool kScalar = std::is_same_v<V, double>;
  // Unsigned where the arithmetic wraps.
  using U =
      std::conditional_t<kScalar, std::uint64_t, std::uint64_t __attribute__((vector_size(8 * kLanes)))>;
  using S = std::conditional_t<kScalar, std::int64_t, M8>;
  const U bits = __builtin_bit_cast(U, x);
  // Subtracting the bits of sqrt(1/2) puts the mantissa cut at sqrt(1/2) instead of 1.
  const U shifted = bits - 0x3fe6a09e667f3bcdull;
  const S k = __builtin_bit_cast(S, shifted) >> 52;  // arithmetic shift
  const U mbits = bits - (__builtin_bit_cast(U, k) << 52);
  const V m = __builtin_bit_cast(V, mbits);
  const V f = m - 1.0;
  const V s = f / (2.0 + f);
  const V z = s * s, w = z * z;
  const V t1 = w * (3.999999999940941908e-01 + w * (2.222219843214978396e-01 + w * 1.531383769920937332e-01));
  const V t2 =
      z * (6.666666666666735130e-01 +
           w * (2.857142874366239149e-01 + w * (1.818357216161805012e-01 + w * 1.479819860511658591e-01)));
  const V r = t2 + t1;
  const V hfsq = 0.5 * f * f;
  V dk;
  if constexpr (kScalar) {
    dk = static_cast<double>(k);
  } else {
    // k is a small integer (x >= 2^-33): convert through 32 bits, which every ISA does in one step.
    dk = __builtin_convertvector(__builtin_convertvector(k, I8), D8);
  }
  return dk * 6.93147180369123816490e-01 - ((hfsq - (s * (hfsq + r) + dk * 1.90821492927058770002e-10)) - f);
}

}  // namespace tocd::sim::mc::lanes
