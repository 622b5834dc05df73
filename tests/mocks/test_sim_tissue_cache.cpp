// The simulated sample's cache: a hit gives back the very tables that were stored, a changed
// configuration misses, and a damaged or foreign entry is rebuilt rather than trusted.
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

class SimTissueCache : public mocks::testing::SimTissueCacheFixture {
 protected:
  mocks::SimTissueTable table_for(const mocks::SimTissueSpec& s) {
    mocks::SimTissueTable t;
    for (std::size_t k = 0; k <= s.displacements_mm.size(); ++k) {
      t.displacement_mm.push_back(k == 0 ? 0.0 : s.displacements_mm[k - 1]);
      t.load_N.push_back(0.1 * static_cast<double>(k) + 1.0 / 3.0);  // not exact in decimal
      t.transmission.push_back(0.9 - 0.1 * static_cast<double>(k));
      t.transmission_stderr.push_back(0.01);
    }
    return t;
  }
};

using tocd::test::read_file;

}  // namespace

TEST_F(SimTissueCache, StoredTablesReadBackBitForBit) {
  const auto file = mocks::sim_tissue_cache_file(dir_, spec_);
  const auto stored = table_for(spec_);
  mocks::store_sim_tissue_table(file, spec_, stored);
  std::string why;
  const auto loaded = mocks::load_sim_tissue_table(file, spec_, why);
  ASSERT_TRUE(loaded) << why;
  EXPECT_EQ(loaded->displacement_mm, stored.displacement_mm);
  EXPECT_EQ(loaded->load_N, stored.load_N);  // exact: 1/3 survives the text round trip
  EXPECT_EQ(loaded->transmission, stored.transmission);
  EXPECT_EQ(loaded->transmission_stderr, stored.transmission_stderr);
}

TEST_F(SimTissueCache, KeyCoversWhatChangesTheTablesOnly) {
  auto other = spec_;
  other.threads = 8;  // results do not depend on threads: same entry
  EXPECT_EQ(mocks::sim_tissue_cache_file(dir_, spec_), mocks::sim_tissue_cache_file(dir_, other));
  for (auto change :
       {+[](mocks::SimTissueSpec& s) { s.seed += 1; }, +[](mocks::SimTissueSpec& s) { s.photons += 1; },
        +[](mocks::SimTissueSpec& s) { s.thickness_mm += 1e-12; },
        +[](mocks::SimTissueSpec& s) { s.stiffness_scale *= 2; },
        +[](mocks::SimTissueSpec& s) { s.optics_model = "threshold"; },
        +[](mocks::SimTissueSpec& s) { s.displacements_mm.push_back(0.75); }}) {
    auto changed = spec_;
    change(changed);
    EXPECT_NE(mocks::sim_tissue_cache_key(spec_), mocks::sim_tissue_cache_key(changed));
    EXPECT_NE(mocks::sim_tissue_cache_file(dir_, spec_), mocks::sim_tissue_cache_file(dir_, changed));
  }
}

TEST_F(SimTissueCache, ForeignCorruptOrInconsistentEntriesAreRefused) {
  const auto file = mocks::sim_tissue_cache_file(dir_, spec_);
  std::string why;
  EXPECT_FALSE(mocks::load_sim_tissue_table(file, spec_, why));  // absent
  EXPECT_NE(why.find("no cache entry"), std::string::npos) << why;

  // Another configuration's entry under this name (a hash collision, a copied file).
  auto other = spec_;
  other.seed = 99;
  mocks::store_sim_tissue_table(file, other, table_for(other));
  EXPECT_FALSE(mocks::load_sim_tissue_table(file, spec_, why));
  EXPECT_NE(why.find("another configuration"), std::string::npos) << why;

  // Truncated mid-write by something other than tocdlab.
  mocks::store_sim_tissue_table(file, spec_, table_for(spec_));
  const std::string good = read_file(file);
  tocd::test::write_file(file, good.substr(0, good.size() / 2));
  EXPECT_FALSE(mocks::load_sim_tissue_table(file, spec_, why));
  EXPECT_NE(why.find("unreadable"), std::string::npos) << why;

  // Valid JSON, right key, but a table that cannot be this spec's.
  auto bad = table_for(spec_);
  bad.transmission.pop_back();
  mocks::store_sim_tissue_table(file, spec_, bad);
  EXPECT_FALSE(mocks::load_sim_tissue_table(file, spec_, why));
  EXPECT_NE(why.find("rows"), std::string::npos) << why;
}
