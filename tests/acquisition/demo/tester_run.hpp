#pragma once

// Fixtures of the tests that read a recorded run: a temporary database, and a run with the
// tester's displacement and load channels as the engine creates them.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/db/database.hpp"

namespace tocd::acquisition::testing {

struct TesterRun {
  std::int64_t run_id = 0, displacement_channel = 0, load_channel = 0;
};

/// A skin sample of `thickness_mm` (NaN: none recorded), a run on it and the two channels.
inline TesterRun create_tester_run(db::Database& db, double thickness_mm, const std::string& name) {
  db::SampleRecord sample;
  sample.tissue = "skin";
  if (std::isfinite(thickness_mm)) sample.thickness_mm = thickness_mm;
  db::NewRun nr;
  nr.name = name;
  nr.sample_id = db.add_sample(sample);
  TesterRun out;
  out.run_id = db.create_run(nr).id;
  db::Channel dc, lc;
  dc.run_id = lc.run_id = out.run_id;
  dc.name = "displacement";
  dc.unit = "mm";
  lc.name = "load";
  lc.unit = "N";
  out.displacement_channel = db.add_channel(dc).id;
  out.load_channel = db.add_channel(lc).id;
  return out;
}

/// A database file of its own per test suite and process, removed with its side files after
/// each test.
class TempDatabaseTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string suite = ::testing::UnitTest::GetInstance()->current_test_suite()->name();
    path_ =
        std::filesystem::temp_directory_path() / ("tocd_" + suite + "_" + std::to_string(::getpid()) + ".db");
    std::filesystem::remove(path_);
  }
  void TearDown() override {
    for (const char* ext : {"", "-wal", "-shm", "-runlock"}) std::filesystem::remove(path_.string() + ext);
  }
  std::filesystem::path path_;
};

}  // namespace tocd::acquisition::testing
