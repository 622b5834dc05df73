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
#include "tocd/test/temp_dir.hpp"

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

/// A database file of its own per test, removed with its folder (and side files) after it.
class TempDatabaseTest : public ::testing::Test {
 protected:
  tocd::test::TempDir dir_{"acq_db"};
  std::filesystem::path path_ = dir_ / "runs.db";
};

}  // namespace tocd::acquisition::testing
