#pragma once

// The cache tests' tiny simulated sample (one displacement, 300 photons, one thread) and a
// directory of its own for each test's cache.

#include <gtest/gtest.h>

#include "tocd/mocks/sim_tissue.hpp"
#include "tocd/test/temp_dir.hpp"

namespace tocd::mocks::testing {

class SimTissueCacheFixture : public ::testing::Test {
 protected:
  SimTissueCacheFixture() {
    spec_.displacements_mm = {0.5};
    spec_.photons = 300;
    spec_.threads = 1;
  }

  tocd::test::TempDir dir_{"sim_cache"};
  SimTissueSpec spec_;
};

}  // namespace tocd::mocks::testing
