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

namespace tocd::acquisition::testing {

class EngineFixture : public ::testing::Test {
 protected:
  static constexpr double kFactor = 20.0;  // simulated seconds per real second

  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           fmt::format("tocd_engine_{}_{}_{}", ::getpid(),
                       ::testing::UnitTest::GetInstance()->current_test_info()->test_suite_name(),
                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    path_ = dir_ / "runs.db";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  static EngineOptions fast() {
    EngineOptions o;
    o.clock_factor = kFactor;
    return o;
  }

  /// Polls `pred` every 2 ms for up to `seconds` of real time.
  template <class Pred>
  static bool eventually(Pred pred, double seconds = 20.0) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
      if (pred()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return pred();
  }

  static bool has_event(const tocd::db::Reader& r, std::int64_t run, const std::string& kind,
                        const std::string& text) {
    for (const auto& e : r.events(run))
      if (e.kind == kind && e.message.find(text) != std::string::npos) return true;
    return false;
  }

  std::filesystem::path dir_, path_;
};

}  // namespace tocd::acquisition::testing
