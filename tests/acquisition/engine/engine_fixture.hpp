#pragma once
// The run engine's test fixture, shared by its suites: a fresh directory with a database path
// per test, the engine's options at a fast simulated clock, and the waits the suites need.
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/acquisition/engine.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/eventually.hpp"
#include "tocd/test/temp_dir.hpp"

namespace tocd::acquisition::testing {

// The suites wait with the shared poll (every 2 ms, up to 20 s unless they say otherwise).
using tocd::test::eventually;

class EngineFixture : public ::testing::Test {
 protected:
  static constexpr double kFactor = 20.0;  // simulated seconds per real second

  static EngineOptions fast() {
    EngineOptions o;
    o.clock_factor = kFactor;
    return o;
  }

  static bool has_event(const tocd::db::Reader& r, std::int64_t run, const std::string& kind,
                        const std::string& text) {
    for (const auto& e : r.events(run))
      if (e.kind == kind && e.message.find(text) != std::string::npos) return true;
    return false;
  }

  tocd::test::TempDir dir_{"engine"};
  std::filesystem::path path_ = dir_ / "runs.db";
};

}  // namespace tocd::acquisition::testing
