// db_bench [seconds=5] [file=db_bench.sqlite | postgresql://...]
// Into an SQLite file (target 200,000 samples/s) or a PostgreSQL server (target 100,000
// samples/s per rig; give it a scratch database: its runs stay there).
// 1) Drain rate of a 3-million-sample backlog. 2) 250,000 (server: 125,000) samples/s offered for `seconds`
//    with a reader polling the run as the GUI would. 3) Acquisition shape: 10 minutes of 1 kHz load +
//    displacement and 10 Hz power + pressure, enqueued as fast as possible; every sample must arrive (dropped
//    = 0, written = expected).
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "tocd/core/clock.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/location.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace {

using namespace tocd::db;
using Clock = std::chrono::steady_clock;

void remove_db(const std::filesystem::path& p) {
  if (is_server_uri(p.string())) return;  // each phase records a run of its own there
  for (const char* suffix : {"", "-wal", "-shm", "-runlock"}) std::filesystem::remove(p.string() + suffix);
}

// The write rate a backend must sustain: a file 200,000 samples/s, a server 100,000 per rig.
double target(const std::filesystem::path& p) {
  return is_server_uri(p.string()) ? 100'000 : 200'000;
}

void print_stats(const WriterStats& s) {
  fmt::print(
      "  batches {}  batch commit latency mean {:.2f} ms  max {:.2f} ms  enqueue-to-commit max {:.1f} ms  "
      "queue high water {}  writer CPU {:.2f} s\n",
      s.batches, s.mean_batch_ms, s.max_batch_ms, s.max_commit_delay_ms, s.queue_high_water,
      s.writer_cpu_seconds);
  fmt::print("  enqueued {}  written {}  dropped {}  rejected {}  failed {}\n", s.enqueued, s.written,
             s.dropped, s.rejected, s.failed);
}

// The drain and sustained phases record this many channels of one run.
constexpr int kChannels = 4;

// A new run in `db` with kChannels voltage channels; their ids.
std::vector<std::int64_t> run_with_channels(Database& db) {
  const auto run = db.create_run({}).id;
  std::vector<std::int64_t> ch;
  for (int i = 0; i < kChannels; ++i)
    ch.push_back(db.add_channel({0, run, fmt::format("ch{}", i), "V", 0, kUnset}).id);
  return ch;
}

// Writer drain rate: producers enqueue a backlog far faster than any disk, the writer drains
// it; samples/s = samples / (time until the last one is committed).
bool drain(const std::filesystem::path& path, std::int64_t total) {
  remove_db(path);
  Database db(path);
  const std::vector<std::int64_t> ch = run_with_channels(db);
  WriterOptions wo;
  wo.queue_capacity = static_cast<std::size_t>(total) + 1;  // the bench measures commits, not drops
  Writer w(db, wo);
  const auto t0 = Clock::now();
  const auto base = tocd::monotonic_ns();
  std::vector<Sample> block(1000);
  for (std::int64_t i = 0; i < total; i += kChannels) {
    for (int c = 0; c < kChannels; ++c)
      block[static_cast<std::size_t>((i + c) % 1000)] = {ch[c], base + i * 250, 1.0 * i};
    if ((i + kChannels) % 1000 == 0) w.enqueue(block);
  }
  w.flush();
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto s = w.stats();
  const bool file = !is_server_uri(path.string());
  const auto bytes =
      !file ? 0
            : std::filesystem::file_size(path) + (std::filesystem::exists(path.string() + "-wal")
                                                      ? std::filesystem::file_size(path.string() + "-wal")
                                                      : 0);
  fmt::print(
      "drain: {:.0f} samples/s ({} samples, {} channels, {:.2f} s wall; writer thread CPU {:.2f} s = {:.0f} "
      "samples per CPU-s)\n",
      static_cast<double>(s.written) / elapsed, s.written, kChannels, elapsed, s.writer_cpu_seconds,
      static_cast<double>(s.written) / s.writer_cpu_seconds);
  print_stats(s);
  if (file)
    fmt::print("  file {:.1f} MB, {:.1f} bytes/sample\n", static_cast<double>(bytes) / 1e6,
               static_cast<double>(bytes) / static_cast<double>(s.written));
  return s.dropped == 0 && s.written == s.enqueued &&
         static_cast<double>(s.written) / elapsed >= target(path);
}

// Sustained: producers at a fixed rate (4 channels, paced every millisecond) for `seconds`,
// a reader polling the newest second min/max-decimated as the GUI does. The writer keeps up
// when the queue never grows beyond a few batch intervals' worth and nothing is dropped.
bool sustained(const std::filesystem::path& path, double seconds, double rate) {
  remove_db(path);
  Database db(path);
  const std::vector<std::int64_t> ch = run_with_channels(db);
  Writer w(db);
  std::atomic<bool> stop{false};
  std::atomic<std::int64_t> reads{0};
  std::thread reader([&] {
    Reader rd(path);
    while (!stop.load()) {
      SampleQuery q;
      q.decimation = Decimation::min_max;
      q.max_points = 1000;
      q.from_t_ns = tocd::monotonic_ns() - 1'000'000'000;
      rd.samples(ch[0], q);
      ++reads;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  const auto t0 = Clock::now();
  std::int64_t made = 0;
  std::vector<Sample> block;
  for (;;) {
    const double now = std::chrono::duration<double>(Clock::now() - t0).count();
    if (now >= seconds) break;
    const auto due = static_cast<std::int64_t>(now * rate);
    block.clear();
    const auto t = tocd::monotonic_ns();
    for (; made < due; ++made) block.push_back({ch[made % kChannels], t + made, 1.0 * made});
    w.enqueue(block);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  stop = true;
  reader.join();
  const auto before_flush = w.stats();
  w.flush();
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto s = w.stats();
  fmt::print(
      "sustained: {:.0f} samples/s offered for {:.1f} s -> {:.0f} samples/s committed ({} samples, "
      "{:.2f} s incl. final flush; backlog at the end {}; {} reader polls)\n",
      rate, seconds, static_cast<double>(s.written) / elapsed, s.written, elapsed, before_flush.queue_depth,
      reads.load());
  print_stats(s);
  return s.dropped == 0 && s.written == s.enqueued && static_cast<double>(s.written) / elapsed >= 0.95 * rate;
}

bool acquisition_shape(const std::filesystem::path& path) {
  remove_db(path);
  Database db(path);
  const auto run = db.create_run({}).id;
  const auto load = db.add_channel({0, run, "load", "N", 0, 1000.0}).id;
  const auto disp = db.add_channel({0, run, "displacement", "mm", 0, 1000.0}).id;
  const auto power = db.add_channel({0, run, "power", "W", 0, 10.0}).id;
  const auto pressure = db.add_channel({0, run, "pressure", "kPa", 0, 10.0}).id;
  constexpr std::int64_t kSeconds = 600, kMs = kSeconds * 1000;
  const auto t_start = tocd::monotonic_ns();
  const auto t0 = Clock::now();
  Writer w(db);
  for (std::int64_t ms = 0; ms < kMs; ++ms) {
    const auto t = t_start + ms * 1'000'000;
    w.enqueue(Sample{load, t, 1.0});
    w.enqueue(Sample{disp, t, 0.5});
    if (ms % 100 == 0) {
      w.enqueue(Sample{power, t, 5e-4});
      w.enqueue(Sample{pressure, t, -20.0});
    }
  }
  w.flush();
  const double elapsed = std::chrono::duration<double>(Clock::now() - t0).count();
  const auto s = w.stats();
  const std::uint64_t expected = 2 * kMs + 2 * (kMs / 100);
  Reader rd(path);
  const auto counted =
      rd.sample_count(load) + rd.sample_count(disp) + rd.sample_count(power) + rd.sample_count(pressure);
  fmt::print(
      "acquisition shape (10 min of 2 x 1 kHz + 2 x 10 Hz, enqueued at full speed): {} expected, {} in file, "
      "{} dropped; {:.2f} s ({:.0f} samples/s)\n",
      expected, counted, s.dropped, elapsed, static_cast<double>(counted) / elapsed);
  print_stats(s);
  return s.dropped == 0 && static_cast<std::uint64_t>(counted) == expected;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 5.0;
  const std::filesystem::path path = argc > 2 ? argv[2] : "db_bench.sqlite";
  fmt::print("into {}\n", display_location(path.string()));
  const bool ok0 = drain(path, 3'000'000);
  const bool ok1 = sustained(path, seconds, 1.25 * target(path));
  const bool ok2 = acquisition_shape(path);
  remove_db(path);
  const bool ok = ok0 && ok1 && ok2;
  fmt::print(
      "{}\n",
      ok ? fmt::format("PASS (>= {:.0f} samples/s sustained, no sample lost)", target(path))
         : fmt::format("BELOW TARGET (on a loaded machine compare samples per writer CPU-s with {:.0f})",
                       target(path)));
  return ok ? 0 : 1;
}
