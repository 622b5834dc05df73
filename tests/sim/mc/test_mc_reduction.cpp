// The exact (order-free) tallies: sums that do not depend on the order of addition, and a
// run split into blocks of batches that adds up to the whole run bit for bit. This is what
// lets MPI ranks share a run without changing a single bit of its result.
#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>

#include <gtest/gtest.h>

#include "exact_sum.hpp"
#include "slab_fixture.hpp"

namespace mc = tocd::sim::mc;
using namespace tocd::sim::mc::testing;

namespace {

using Words = std::array<std::int64_t, mc::kExactLimbs>;

Words sum_of(const std::vector<double>& xs) {
  Words w{};
  for (double x : xs) mc::exact_add(x, w.data());
  return w;
}

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

}  // namespace

TEST(McExactSum, TheOrderOfAdditionDoesNotMatter) {
  // Values over 30 decades, both signs: a plain double sum of them depends on the order.
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> mantissa(0.5, 1.0);
  std::uniform_int_distribution<int> exponent(-70, 30);
  std::vector<double> xs(20000);
  for (auto& x : xs) x = std::ldexp(mantissa(gen), exponent(gen)) * (gen() % 3 == 0 ? -1.0 : 1.0);
  const double forward = mc::exact_value(sum_of(xs).data());
  std::vector<double> reversed(xs.rbegin(), xs.rend()), shuffled = xs;
  std::shuffle(shuffled.begin(), shuffled.end(), gen);
  EXPECT_TRUE(same_bits(forward, mc::exact_value(sum_of(reversed).data())));
  EXPECT_TRUE(same_bits(forward, mc::exact_value(sum_of(shuffled).data())));
  // Three partial sums combined limb by limb, as MPI_SUM combines the ranks' tallies.
  Words parts{};
  for (int p = 0; p < 3; ++p) {
    const Words w = sum_of({xs.begin() + p * 6000, p == 2 ? xs.end() : xs.begin() + (p + 1) * 6000});
    for (int k = 0; k < mc::kExactLimbs; ++k)
      parts[static_cast<std::size_t>(k)] += w[static_cast<std::size_t>(k)];
  }
  EXPECT_TRUE(same_bits(forward, mc::exact_value(parts.data())));
  // A naive double sum of the same values in two orders differs (that is the point).
  const double naive_f = std::accumulate(xs.begin(), xs.end(), 0.0);
  const double naive_r = std::accumulate(reversed.begin(), reversed.end(), 0.0);
  EXPECT_NEAR(forward, naive_f, 1e-6 * std::fabs(forward));
  EXPECT_NE(naive_f, naive_r);
}

TEST(McExactSum, SumsOfDyadicValuesAreExact) {
  // Multiples of 2^-40 up to 2^20: their true sum is an integer multiple of 2^-40 that int64
  // holds exactly, an independent reference.
  std::mt19937_64 gen(9);
  std::uniform_int_distribution<std::int64_t> k(-(std::int64_t{1} << 60), std::int64_t{1} << 60);
  std::vector<double> xs;
  std::int64_t total = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::int64_t ki = k(gen) >> 10;  // |ki| < 2^50: exact in a double
    total += ki;
    xs.push_back(std::ldexp(static_cast<double>(ki), -40));
  }
  EXPECT_EQ(mc::exact_value(sum_of(xs).data()), std::ldexp(static_cast<double>(total), -40));
  // Cancellation a double sum loses entirely: 2^60 + 1 - 2^60.
  EXPECT_EQ(mc::exact_value(sum_of({std::ldexp(1.0, 60), 1.0, -std::ldexp(1.0, 60)}).data()), 1.0);
  // Tiny values are kept down to 2^-128.
  EXPECT_EQ(mc::exact_value(sum_of({std::ldexp(1.0, -120), std::ldexp(1.0, -120)}).data()),
            std::ldexp(1.0, -119));
}

TEST(McReduction, BlocksOfBatchesAddUpToTheWholeRun) {
  const mc::PreparedMesh mesh = slab(6.0, 1.0, 3, 2);
  const mc::Optics optics = one_region(props(0.2, 8.0, 0.8, 1.4));
  mc::RunSettings s = settings(20000, 3, 2);
  s.tally_per_tet = true;
  const mc::Result whole = mc::run(mesh, optics, pencil(), s);

  // Blocks of uneven size run with different thread counts, summed in reverse order.
  mc::Tallies sum;
  const int bounds[] = {0, 7, 13, 20};
  for (int b = 2; b >= 0; --b) {
    s.threads = 1 + b % 2;
    const mc::Tallies part = mc::run_batches(mesh, optics, pencil(), s, bounds[b], bounds[b + 1]);
    if (sum.words.empty()) sum.words.assign(part.words.size(), 0);
    for (std::size_t i = 0; i < part.words.size(); ++i) sum.words[i] += part.words[i];
  }
  const mc::Result split = mc::finish(mesh, optics, s, sum);
  EXPECT_EQ(split.photons, whole.photons);
  EXPECT_EQ(split.batches, 20);
  EXPECT_EQ(split.events, whole.events);
  EXPECT_EQ(split.face_hits, whole.face_hits);
  for (auto [a, b] : {std::pair{split.transmittance, whole.transmittance},
                      {split.reflectance, whole.reflectance},
                      {split.absorbed, whole.absorbed},
                      {split.side_loss, whole.side_loss},
                      {split.specular, whole.specular}}) {
    EXPECT_TRUE(same_bits(a.mean, b.mean));
    EXPECT_TRUE(same_bits(a.se, b.se));
  }
  EXPECT_TRUE(same_bits(split.energy_balance_error, whole.energy_balance_error));
  ASSERT_EQ(split.fluence_per_tet.size(), whole.fluence_per_tet.size());
  for (std::size_t t = 0; t < whole.fluence_per_tet.size(); ++t) {
    EXPECT_TRUE(same_bits(split.fluence_per_tet[t], whole.fluence_per_tet[t])) << "tet " << t;
    EXPECT_TRUE(same_bits(split.fluence_per_tet_se[t], whole.fluence_per_tet_se[t])) << "tet " << t;
  }
  // Energy is still conserved to round-off with the exact sums.
  EXPECT_LT(std::fabs(whole.energy_balance_error), 1e-12);
}

TEST(McReduction, TalliesOfAnotherRunAreRefused) {
  const mc::PreparedMesh mesh = slab(6.0, 1.0, 3, 2);
  const mc::Optics optics = one_region(props(0.2, 8.0, 0.8, 1.4));
  mc::RunSettings s = settings(2000, 3, 1);
  s.tally_per_tet = false;
  const mc::Tallies part = mc::run_batches(mesh, optics, pencil(), s, 0, 20);
  s.tally_per_tet = true;  // expects per-tet words the tallies do not have
  EXPECT_THROW(mc::finish(mesh, optics, s, part), tocd::Error);
  EXPECT_THROW(mc::run_batches(mesh, optics, pencil(), s, 5, 21), tocd::ConfigError);
}
