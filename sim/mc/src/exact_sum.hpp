#pragma once

// Order-free sums of doubles: each value is turned into a fixed-point integer (bits from
// 2^-128 to 2^62) kept as six 32-bit limbs in int64 words ("carry-save": a limb may exceed
// 32 bits until normalised). Integer addition is associative, so a total does not depend on
// the order in which batches, threads or MPI ranks are combined; that is what makes the Monte
// Carlo's tallies bitwise identical for any number of ranks and threads.
//
// Range and resolution: |value| < 2^62 (tallies are weights per launched photon, at most the
// photon count); bits below 2^-128 (2.9e-39) are dropped, the same way for every order.
// Each addition adds less than 2^32 to a limb, so 2^31 additions fit before a limb could
// overflow; a run adds once per batch, and batches are capped far below that.
#include <cmath>
#include <cstdint>
#include <span>

namespace tocd::sim::mc {

inline constexpr int kExactLimbs = 6;
inline constexpr int kExactFractionBits = 128;

/// Adds x (finite, |x| < 2^62) to the fixed-point number in w[0..5].
inline void exact_add(double x, std::int64_t* w) noexcept {
  if (x == 0.0) return;
  int e = 0;
  const double f = std::frexp(std::fabs(x), &e);  // |x| = f 2^e, 0.5 <= f < 1
  auto mantissa = static_cast<std::uint64_t>(std::ldexp(f, 53));
  int shift = e - 53 + kExactFractionBits;  // bit position of the mantissa's lowest bit
  if (shift < 0) {
    if (shift <= -53) return;
    mantissa >>= -shift;
    shift = 0;
  }
  const std::int64_t sign = x < 0.0 ? -1 : 1;
  // The mantissa shifted by shift % 32 spans at most 85 bits: three 32-bit pieces.
  const int off = shift % 32;
  const std::uint64_t lo = mantissa << off, hi = off == 0 ? 0 : mantissa >> (64 - off);
  const std::uint64_t piece[3] = {lo & 0xffffffffu, lo >> 32, hi};
  for (int i = 0, k = shift / 32; i < 3 && k < kExactLimbs; ++i, ++k)
    w[k] += sign * static_cast<std::int64_t>(piece[i]);
}

/// The double nearest (to within one unit in the last place) the fixed-point number w.
inline double exact_value(const std::int64_t* w) noexcept {
  // Propagate the carries so every limb but the top one lies in [0, 2^32).
  std::int64_t limb[kExactLimbs];
  std::int64_t carry = 0;
  for (int k = 0; k < kExactLimbs; ++k) {
    const std::int64_t v = w[k] + carry;
    carry = v >> 32;  // floor division by 2^32 (arithmetic shift)
    limb[k] = v - (carry << 32);
  }
  limb[kExactLimbs - 1] += carry << 32;
  long double value = 0.0L;  // 64-bit mantissa: the rounding to double happens once, at the end
  for (int k = kExactLimbs - 1; k >= 0; --k)
    value = value * 4294967296.0L + static_cast<long double>(limb[k]);
  return static_cast<double>(std::ldexp(value, -kExactFractionBits));
}

}  // namespace tocd::sim::mc
