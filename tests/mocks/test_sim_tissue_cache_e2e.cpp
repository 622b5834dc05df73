// The simulated sample's cache end to end: make_simulated_tissue prepares a tiny sample once,
// reads it back on the second call, and prepares it again when the entry is damaged. About a
// minute on a loaded two-core machine (two FE solves + six Monte Carlo points): integration.
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "sim_tissue_cache_fixture.hpp"
#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/mocks/sim_tissue_cache.hpp"
#include "tocd/test/files.hpp"

namespace fs = std::filesystem;
namespace mocks = tocd::mocks;

namespace {

using SimTissueCache = mocks::testing::SimTissueCacheFixture;

}  // namespace

// The whole path through make_simulated_tissue, with a tiny sample (one displacement, 300
// photons): first call prepares and stores, second is a hit with identical tables, a damaged
// entry is prepared again and repaired.
TEST_F(SimTissueCache, PreparedOnceThenReadThenRebuiltWhenDamaged) {
  spec_.cache_dir = dir_;
  mocks::SimTissueTable first, second, third;
  (void)mocks::make_simulated_tissue(spec_, &first);
  EXPECT_FALSE(first.from_cache);
  ASSERT_TRUE(fs::exists(first.cache_file)) << first.cache_file;

  (void)mocks::make_simulated_tissue(spec_, &second);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.transmission, first.transmission);
  EXPECT_EQ(second.load_N, first.load_N);

  tocd::test::write_file(first.cache_file, "{\"key\": 1, ");  // damaged
  (void)mocks::make_simulated_tissue(spec_, &third);
  EXPECT_FALSE(third.from_cache);
  EXPECT_EQ(third.transmission, first.transmission);  // same seed: the same tables again
  std::string why;
  EXPECT_TRUE(mocks::load_sim_tissue_table(first.cache_file, spec_, why)) << why;  // repaired
}
