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
#include "tocd/db/writer.hpp"
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

/// Writes a tester run's samples as the engine streams them: one (displacement, load) pair
/// per microsecond of the run's clock, from t = 1000 ns.
class TesterSampleWriter {
 public:
  TesterSampleWriter(db::Database& db, const TesterRun& run) : writer_(db), run_(run) {}

  void put(double displacement_mm, double load_N) {
    writer_.enqueue(db::Sample{run_.displacement_channel, t_ns_, displacement_mm});
    writer_.enqueue(db::Sample{run_.load_channel, t_ns_, load_N});
    t_ns_ += 1000;
  }
  /// Commits every sample put so far and stops the writer.
  void finish() {
    writer_.flush();
    writer_.stop();
  }

 private:
  db::Writer writer_;
  TesterRun run_;
  std::int64_t t_ns_ = 1000;
};

/// A database file of its own per test, removed with its folder (and side files) after it.
class TempDatabaseTest : public ::testing::Test {
 protected:
  tocd::test::TempDir dir_{"acq_db"};
  std::filesystem::path path_ = dir_ / "runs.db";
};

}  // namespace tocd::acquisition::testing
