// Acquisition at full rate for ten simulated minutes: 1 kHz displacement + load, 10 Hz power
// and pressure, every sample counted from the pollers into the file.
#include <filesystem>

#include <gtest/gtest.h>

#include "fake_rig.hpp"
#include "protocol_text.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/temp_dir.hpp"

using namespace tocd::acquisition;
using namespace tocd::acquisition::testing;
namespace fs = std::filesystem;

TEST(AcquisitionTenMinutes, ZeroLostSamplesAtOneKilohertz) {
  const double factor = 40.0;  // 10 simulated minutes in 15 s
  const tocd::test::TempDir dir("acq_10min");
  auto world = std::make_shared<FakeWorld>(factor);
  tocd::db::Database db(dir / "runs.db");
  EngineOptions opt;
  opt.clock_factor = factor;
  // One step whose recording window fills the ten minutes.
  std::string text = pin_protocol("0.25", 50.0, 600.0, 1000.0);
  Engine engine(db, make_fake_instruments(world, true, true), opt);
  const auto run = engine.start(parse_protocol(text, "ten_minutes.toml"));
  ASSERT_EQ(engine.wait(), EngineState::completed) << engine.error();

  const auto stats = engine.stats();
  const tocd::db::Reader r(dir / "runs.db");
  std::int64_t stored = 0;
  std::map<std::string, std::int64_t> per_channel;
  for (const auto& c : r.channels(run)) {
    per_channel[c.name] = r.sample_count(c.id);
    stored += per_channel[c.name];
  }
  EXPECT_EQ(stats.samples_dropped, 0u);
  EXPECT_EQ(stats.writer.rejected, 0u);
  EXPECT_EQ(stats.poll_overruns, 0u);
  EXPECT_EQ(static_cast<std::uint64_t>(stored), stats.samples_enqueued);
  EXPECT_EQ(stats.writer.written, stats.writer.enqueued);

  // The rates held over the whole run: samples = rate x recorded span (+- 0.1 %).
  const auto load = r.samples(r.channel(run, "load")->id);
  ASSERT_GT(load.size(), 2u);
  const double span_s = static_cast<double>(load.back().t_ns - load.front().t_ns) * 1e-9;
  EXPECT_GT(span_s, 600.0);
  EXPECT_NEAR(static_cast<double>(per_channel["load"]), 1000.0 * span_s, 1e-3 * 1000.0 * span_s);
  EXPECT_EQ(per_channel["load"], per_channel["displacement"]);
  EXPECT_NEAR(static_cast<double>(per_channel["power"]), 10.0 * span_s, 2.0 + 1e-3 * 10.0 * span_s);
  EXPECT_NEAR(static_cast<double>(per_channel["pressure"]), 10.0 * span_s, 2.0 + 1e-3 * 10.0 * span_s);
  std::cout << fmt::format(
      "ten simulated minutes: {} samples stored ({} load), writer {} batches, "
      "mean commit {:.1f} ms, max {:.1f} ms, queue high water {}\n",
      stored, per_channel["load"], stats.writer.batches, stats.writer.mean_batch_ms,
      stats.writer.max_batch_ms, stats.writer.queue_high_water);
}
