// The vector lanes of the transport kernel (sim/mc/src/lanes.hpp) against their scalar
// counterparts: each lane's random stream is its photon's PhotonRng draw for draw, whatever
// the other lanes do; the logarithm agrees with the C library's, in every lane as in its
// scalar form; the transpose puts
// record i's column c in lane i of column c. Reads the private header directly.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>

#include <gtest/gtest.h>

#include "lanes.hpp"

namespace mc = tocd::sim::mc;
namespace lanes = tocd::sim::mc::lanes;

namespace {

TEST(McLanes, EachLaneDrawsItsPhotonsStreamWhateverTheOtherLanesDo) {
  mc::PhotonRng scalar[lanes::kLanes];
  lanes::Rng vec{};
  for (int i = 0; i < lanes::kLanes; ++i) {
    scalar[i] = mc::PhotonRng(12345, 1000 + i);
    vec.set(i, scalar[i]);
  }
  std::mt19937 pick(7);
  for (int round = 0; round < 2000; ++round) {
    const unsigned advance = pick() & 0xffu;  // lanes drawing this round
    const lanes::U8 drawn = vec.bits(lanes::mask_of(advance));
    for (int i = 0; i < lanes::kLanes; ++i) {
      if ((advance >> i) & 1u) {
        ASSERT_EQ(drawn[i], scalar[i].bits()) << "lane " << i << ", round " << round;
      }
      for (int k = 0; k < 4; ++k) ASSERT_EQ(vec.lane(i).state(k), scalar[i].state(k)) << "lane " << i;
    }
  }
  // uniform() as PhotonRng::uniform, bit for bit.
  const lanes::D8 u = vec.uniform(lanes::mask_of(0xffu));
  for (int i = 0; i < lanes::kLanes; ++i) EXPECT_EQ(u[i], scalar[i].uniform());
}

TEST(McLanes, LogarithmAgreesWithTheLibraryOnTheUnitInterval) {
  // The free paths' logarithm of a uniform draw: arguments from 2^-32 (the smallest draw) to
  // 1. fdlibm's series is within 1 ulp of the exact value, and so is glibc's log: 2 ulp apart
  // at most.
  std::mt19937_64 gen(11);
  std::uniform_real_distribution<double> exponent(-32.0, 0.0);
  double worst_ulps = 0.0;
  for (int round = 0; round < 20000; ++round) {
    lanes::D8 x;
    for (int i = 0; i < lanes::kLanes; ++i) x[i] = std::exp2(exponent(gen));
    if (round == 0) x[0] = 1.0, x[1] = 0x1p-32, x[2] = std::nextafter(1.0, 0.0), x[3] = 0.5;
    const lanes::D8 y = lanes::log_unit(x);
    for (int i = 0; i < lanes::kLanes; ++i) {
      const double ref = std::log(x[i]);
      const double ulp = ref == 0.0 ? 0x1p-1074 : std::abs(std::nextafter(ref, 0.0) - ref);
      worst_ulps = std::max(worst_ulps, std::abs(y[i] - ref) / ulp);
      ASSERT_EQ(y[i], lanes::log_unit(x[i])) << "the scalar form differs at " << x[i];
    }
  }
  EXPECT_LE(worst_ulps, 2.0);
}

TEST(McLanes, TransposePutsRecordIColumnCInLaneIOfColumnC) {
  lanes::F16 rows[lanes::kLanes];
  for (int i = 0; i < lanes::kLanes; ++i)
    for (int c = 0; c < 16; ++c) rows[i][c] = static_cast<float>(100 * i + c) + 0.25f;
  lanes::D8 columns[16];
  lanes::transpose(rows, columns);
  for (int c = 0; c < 16; ++c)
    for (int i = 0; i < lanes::kLanes; ++i) EXPECT_EQ(columns[c][i], 100.0 * i + c + 0.25) << "column " << c;
}

TEST(McLanes, MasksAndSignsAsTheirScalarForms) {
  for (unsigned b = 0; b < 256; ++b) EXPECT_EQ(lanes::bits_of(lanes::mask_of(b)), b);
  const lanes::D8 x = {-0.0, 0.0, -3.5, 2.0, -1e-300, 1e300, -HUGE_VAL, HUGE_VAL};
  const lanes::D8 s = lanes::copysign_one(x);
  const std::array<double, lanes::kLanes> squares = {0.0, 1.0, 4.0, 2.0, 0.25, 9.0, 1e-300, 1e300};
  lanes::D8 v;
  for (int i = 0; i < lanes::kLanes; ++i) v[i] = squares[i];
  const lanes::D8 r = lanes::sqrt(v);
  for (int i = 0; i < lanes::kLanes; ++i) {
    EXPECT_EQ(s[i], std::copysign(1.0, x[i])) << "lane " << i;
    EXPECT_EQ(r[i], std::sqrt(squares[i])) << "lane " << i;
  }
}

}  // namespace
