// The fault matrix: faults injected into the simulated lab (real wire protocols on loopback)
// in each phase of a step. In every cell the run either recovers and re-records, or pauses /
// ends interrupted with an event naming the fault; then it is resumed to completion. Whatever
// happened, no step is completed at a wrong position or from a window during which an
// instrument fault was recorded. docs/acquisition.md shows the matrix.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "forwarding_tester.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/power_meter_twin.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/mocks/tissue.hpp"
#include "tocd/test/eventually.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/protocol_text.hpp"
#include "tocd/test/sqlite_pages.hpp"
#include "tocd/test/temp_dir.hpp"
#include "trickle_proxy.hpp"

using namespace tocd::acquisition;
namespace fs = std::filesystem;
namespace dev = tocd::devices;

namespace {

constexpr double kFactor = 10.0;

/// The real tester driver, except that the next `refuse` moves ask for 100 mm/s, which the
/// simulated tester refuses on the wire (its maximum is 20 mm/s) with Modbus exception 3.
class RefusingTester : public tocd::acquisition::testing::ForwardingTester {
 public:
  RefusingTester(std::unique_ptr<dev::MechanicalTester> real, std::shared_ptr<std::atomic<int>> refuse)
      : ForwardingTester(std::move(real)), refuse_(std::move(refuse)) {}
  void move_to(double position_mm, double v) override {
    if (position_mm > 0.0 && refuse_->load() > 0) {
      --*refuse_;
      v = 100.0;
    }
    ForwardingTester::move_to(position_mm, v);
  }

 private:
  std::shared_ptr<std::atomic<int>> refuse_;
};

/// The real power-meter driver, except that the next `bad` readings carry `value` (NaN or a
/// negative power), as a meter with a broken sensor or firmware would send them.
class BadReadingMeter : public dev::PowerMeter {
 public:
  BadReadingMeter(std::unique_ptr<dev::PowerMeter> real, std::shared_ptr<std::atomic<int>> bad,
                  std::shared_ptr<std::atomic<double>> value)
      : real_(std::move(real)), bad_(std::move(bad)), value_(std::move(value)) {}
  const dev::InstrumentCapabilities& describe() const override { return real_->describe(); }
  dev::Identity identity() override { return real_->identity(); }
  std::string sensor_identity() override { return real_->sensor_identity(); }
  void set_wavelength_nm(double nm) override { real_->set_wavelength_nm(nm); }
  void set_auto_range(bool on) override { real_->set_auto_range(on); }
  void set_averaging(int n) override { real_->set_averaging(n); }
  void zero() override { real_->zero(); }
  dev::PowerReading measure() override {
    dev::PowerReading r = real_->measure();
    if (bad_->load() > 0) {
      --*bad_;
      r.power_W = value_->load();
    }
    return r;
  }

 private:
  std::unique_ptr<dev::PowerMeter> real_;
  std::shared_ptr<std::atomic<int>> bad_;
  std::shared_ptr<std::atomic<double>> value_;
};

// What the matrix's two protocols share: the simulated sample, 1 s holds, a tester polled at
// 100 Hz (beside the pump too) and a meter at 10 Hz.
template <class ProtocolText>
ProtocolText on_the_matrix_rig(ProtocolText p, const std::string& name) {
  p.name = name;
  p.tissue = "simulated skin";
  p.thickness_mm = 2.5;
  p.hold_s = 1.0;
  p.tester_Hz = 100;
  p.power_Hz = 10;
  return p;
}

std::string pin_protocol() {
  auto p = on_the_matrix_rig(tocd::test::PinProtocolText{}, "fault matrix");
  p.approach_speed_mm_per_s = 0.5;
  p.displacements_mm = "0.25, 0.5";
  p.settle->max_wait_s = 2;
  return tocd::test::protocol_toml(p);
}

std::string vacuum_protocol() {
  auto p = on_the_matrix_rig(tocd::test::VacuumProtocolText{}, "fault matrix, vacuum");
  p.vacuum_kPa = "80, 60";
  p.settle.max_wait_s = 5;
  p.vacuum_loss_kPa.reset();
  return tocd::test::protocol_toml(p);
}

enum class Phase { approach, hold, record };
const char* name(Phase p) {
  return p == Phase::approach ? "approach" : p == Phase::hold ? "hold" : "record";
}
EngineState state_of(Phase p) {
  return p == Phase::approach ? EngineState::moving
         : p == Phase::hold   ? EngineState::holding
                              : EngineState::recording;
}

/// One simulated rig and what the tests can do to it.
struct Rig {
  std::unique_ptr<tocd::mocks::SimulatedLab> lab;
  std::shared_ptr<std::atomic<int>> refuse = std::make_shared<std::atomic<int>>(0);
  std::shared_ptr<std::atomic<int>> bad_power = std::make_shared<std::atomic<int>>(0);
  std::shared_ptr<std::atomic<double>> bad_value = std::make_shared<std::atomic<double>>(0.0);

  /// Between the tester driver and its twin when the cell slows the tester's answers.
  std::unique_ptr<tocd::acquisition::testing::TrickleProxy> tester_proxy;
  /// Processes that only burn CPU at normal priority (a busy machine), killed with the rig.
  std::vector<pid_t> busy;

  ~Rig() {
    for (const pid_t p : busy) {
      ::kill(p, SIGKILL);
      ::waitpid(p, nullptr, 0);
    }
  }
  void start_busy_processes(int n) {
    for (int i = 0; i < n; ++i) {
      const pid_t p = ::fork();
      if (p == 0) {
        volatile unsigned long spin = 0;
        for (;;) spin = spin + 1;
      }
      busy.push_back(p);
    }
  }

  Rig(bool vacuum, bool tester_via_proxy) {
    tocd::mocks::SimulatedLabOptions so;
    so.clock_factor = kFactor;
    so.contact_position_mm = 1.0;
    so.tissue = tocd::mocks::make_analytic_tissue(2.5);
    so.with_vacuum = vacuum;
    lab = std::make_unique<tocd::mocks::SimulatedLab>(so);
    if (tester_via_proxy) {
      tester_proxy =
          std::make_unique<tocd::acquisition::testing::TrickleProxy>(lab->config().tester->address.port);
    }
  }
  InstrumentSet instruments() {
    dev::LabConfig cfg = lab->config();
    if (tester_proxy) cfg.tester->address.port = tester_proxy->port();
    dev::LabInstruments li = dev::open_lab(cfg);
    InstrumentSet s;
    s.tester = std::make_unique<RefusingTester>(std::move(li.tester), refuse);
    s.power_meter = std::make_unique<BadReadingMeter>(std::move(li.power_meter), bad_power, bad_value);
    s.vacuum = std::move(li.vacuum);
    return s;
  }
};

struct Cell {
  std::string fault;
  Phase phase;
  bool vacuum = false;
  std::function<void(Rig&)> inject;
  std::function<void(Rig&)> repair;  ///< what the operator does before resuming
  std::string event_text;            ///< an event naming the fault must contain this ("": none expected)
  bool storage = false;              ///< storage full: the writer may grow the file by a few pages only
  bool armed_before_move = false;    ///< injected while step 1 records, so it meets step 2's move
  bool tester_via_proxy = false;     ///< the tester's answers pass a TrickleProxy the cell can slow
  bool file_size_limit = false;      ///< the OS refuses to grow the database files (ulimit -f)
  bool lab_vacuum = false;           ///< the lab has a vacuum controller though the protocol is a pin one
};

// Names the cell in gtest's messages instead of dumping its bytes.
void PrintTo(const Cell& c, std::ostream* os) {
  *os << c.fault << " during " << name(c.phase);
}

using tocd::test::eventually;

class FaultMatrix : public ::testing::TestWithParam<Cell> {
 protected:
  tocd::test::TempDir dir_{"faults"};
};

/// Sets RLIMIT_FSIZE to a little above the largest of the database's files (WAL included)
/// for as long as it lives, with SIGXFSZ ignored as tocdlab ignores it; restores both.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(const fs::path& db) {
    std::uintmax_t largest = 0;
    for (const char* suffix : {"", "-wal", "-shm"}) {
      std::error_code ec;
      const auto n = fs::file_size(db.string() + suffix, ec);
      if (!ec) largest = std::max(largest, n);
    }
    ::getrlimit(RLIMIT_FSIZE, &before_);
    old_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit r = before_;
    r.rlim_cur = static_cast<rlim_t>(largest + 8 * 1024);
    ::setrlimit(RLIMIT_FSIZE, &r);
  }
  ~FileSizeLimit() {
    ::setrlimit(RLIMIT_FSIZE, &before_);
    std::signal(SIGXFSZ, old_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit before_{};
  void (*old_)(int) = nullptr;
};

using tocd::test::page_count;

std::string all_events(const tocd::db::Reader& r, std::int64_t run) {
  std::string out;
  for (const auto& e : r.events(run)) out += fmt::format("  [{}] {}\n", e.kind, e.message);
  return out;
}

// Some fault, interlock, state or step event of the run names `text`.
void expect_an_event_naming(const fs::path& path, std::int64_t run, const std::string& text) {
  const tocd::db::Reader r(path);
  bool named = false;
  for (const auto& e : r.events(run))
    named = named || ((e.kind == "fault" || e.kind == "interlock" || e.kind == "state" || e.kind == "step") &&
                      e.message.find(text) != std::string::npos);
  EXPECT_TRUE(named) << "no event names '" << text << "':\n" << all_events(r, run);
}

// The run completed every step, each recorded where the step wants it, from a window during
// which no instrument fault was recorded.
void expect_every_step_where_it_should_be(const fs::path& path, std::int64_t run, const Protocol& protocol,
                                          bool vacuum, double vacuum_reached_kPa) {
  const tocd::db::Reader r(path);
  EXPECT_EQ(r.run(run).status, tocd::db::RunStatus::completed) << all_events(r, run);
  const auto steps = r.steps(run);
  ASSERT_EQ(steps.size(), protocol.steps.size()) << all_events(r, run);
  const auto events = r.events(run);
  const auto displacement = r.channel(run, "displacement");
  const auto pressure = r.channel(run, "pressure");
  for (const auto& s : steps) {
    EXPECT_TRUE(s.completed);
    // Recorded where the step wants it...
    if (vacuum) {
      ASSERT_TRUE(pressure);
      EXPECT_NEAR(s.stats_for(pressure->id)->mean, protocol.steps[s.index].pressure_kPa, vacuum_reached_kPa)
          << "step " << s.index;
    } else {
      ASSERT_TRUE(displacement);
      EXPECT_NEAR(s.stats_for(displacement->id)->mean, protocol.steps[s.index].displacement_mm,
                  protocol.position_tolerance_mm)
          << "step " << s.index;
    }
    // ...from a window during which no instrument fault was recorded.
    for (const auto& e : events) {
      // An instrument the protocol does not use voids no window (its faults say so).
      if (e.message.find("not used by this protocol") != std::string::npos) continue;
      if (e.kind == "fault" && e.t_ns >= s.recorded_from_t_ns && e.t_ns <= s.recorded_to_t_ns) {
        ADD_FAILURE() << "step " << s.index << " completed from a window with the fault: " << e.message;
      }
    }
    EXPECT_TRUE(std::isfinite(s.measured_transmission) && s.measured_transmission > 0.0);
  }
}

}  // namespace

TEST_P(FaultMatrix, NoStepIsCompletedAtAWrongPositionOrFromAFaultyWindow) {
  const Cell& cell = GetParam();
  SCOPED_TRACE(fmt::format("{} during {}", cell.fault, name(cell.phase)));
  Rig rig(cell.vacuum || cell.lab_vacuum, cell.tester_via_proxy);
  const fs::path path = dir_ / "runs.db";
  tocd::db::Database db(path);
  const Protocol protocol = parse_protocol(cell.vacuum ? vacuum_protocol() : pin_protocol(), "matrix.toml");
  EngineOptions opt;
  opt.clock_factor = kFactor;
  if (cell.storage) opt.writer.max_page_count = page_count(path) + 12;  // ~1000 samples more
  std::int64_t run = 0;
  EngineState first_end;
  {
    Engine engine(db, rig.instruments(), opt);
    run = engine.start(protocol);
    // The fault strikes in the chosen phase of the second step (the first one is recorded
    // cleanly, so the run has something to keep).
    const int at_step = cell.armed_before_move ? 0 : 1;
    const EngineState at_state = cell.armed_before_move ? EngineState::recording : state_of(cell.phase);
    if (!cell.storage) {
      // One snapshot: the step and the state it is in.
      ASSERT_TRUE(eventually(
          [&] {
            const Progress p = engine.progress();
            return p.step_index == at_step && p.state == at_state;
          },
          60.0));
    }
    // A file-size limit (ulimit -f) a little above what the files hold now: the writes beyond
    // it fail with EFBIG (SIGXFSZ ignored, as tocdlab does) as on a full disk.
    std::optional<FileSizeLimit> limit;
    if (cell.file_size_limit) limit.emplace(path);
    cell.inject(rig);
    // It recovers (and re-records), pauses, or ends interrupted. A pause is resumed (after the
    // operator's repair) as often as it comes, within bounds: a fault that outlasts a few
    // recordings pauses the run again.
    for (int resumes = 0;; ++resumes) {
      ASSERT_TRUE(eventually(
          [&] { return is_terminal(engine.state()) || engine.state() == EngineState::paused; }, 60.0))
          << to_string(engine.state());
      if (engine.state() != EngineState::paused) break;
      ASSERT_LT(resumes, 5) << "still pausing after 5 resumes";
      if (cell.repair) cell.repair(rig);
      engine.resume();
      ASSERT_TRUE(eventually([&] { return engine.state() != EngineState::paused; }, 10.0));
    }
    first_end = engine.wait();
    if (cell.file_size_limit) {
      EXPECT_NE(first_end, EngineState::completed) << "the limit was never reached";
      EXPECT_NE(engine.error().find("storage"), std::string::npos) << engine.error();
    }
  }
  if (!cell.event_text.empty()) expect_an_event_naming(path, run, cell.event_text);
  if (first_end != EngineState::completed) {
    EXPECT_EQ(first_end, EngineState::interrupted);
    if (cell.repair) cell.repair(rig);
    EngineOptions again = opt;
    again.writer.max_page_count = 0;  // the operator made room
    Engine engine(db, rig.instruments(), again);
    engine.resume(run);
    EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
  }

  expect_every_step_where_it_should_be(path, run, protocol, cell.vacuum, opt.vacuum_reached_kPa);
}

namespace {

std::vector<Cell> cells() {
  using tocd::mocks::ModbusFaultKind;
  std::vector<Cell> out;
  // The tester refuses step 2's move on the wire (asked at 100 mm/s, beyond its 20 mm/s).
  Cell refused{"move refused", Phase::approach,
               false,          [](Rig& r) { *r.refuse = 1; },
               nullptr,        "did not carry out 'move to 1.5000 mm"};
  refused.armed_before_move = true;
  out.push_back(refused);
  for (const Phase ph : {Phase::approach, Phase::hold, Phase::record}) {
    // The driver reconnects within its own retries: no fault reaches the engine.
    out.push_back(
        {"tester link dropped", ph, false, [](Rig& r) { r.lab->drop_tester_connections(); }, nullptr, ""});
    out.push_back({"tester not answering", ph, false,
                   [](Rig& r) {
                     r.lab->inject_tester_fault({ModbusFaultKind::no_reply, 4});
                   },
                   nullptr, "mechanical tester"});
    out.push_back({"meter timeout", ph, false, [](Rig& r) { r.lab->power_meter()->swallow_replies(2); },
                   nullptr, "power meter"});
    out.push_back({"meter garbage", ph, false, [](Rig& r) { r.lab->power_meter()->garbage_replies(2); },
                   nullptr, "power meter"});
    out.push_back({"meter NaN", ph, false,
                   [](Rig& r) {
                     *r.bad_value = std::nan("");
                     *r.bad_power = 2;
                   },
                   nullptr, "power meter: reading nan W is not a number"});
    out.push_back({"meter negative", ph, false,
                   [](Rig& r) {
                     *r.bad_value = -1e-4;
                     *r.bad_power = 2;
                   },
                   nullptr, "is negative beyond the sensor's zero noise"});
    // The meter answers 9.9E37 (SCPI's overflow): the protocol's over-range interlock (on by
    // default) pauses the run, and the operator resumes it once the light is back in range.
    out.push_back({"meter over range", ph, false,
                   [](Rig& r) { r.lab->power_meter()->over_range_readings(3); }, nullptr,
                   "power meter over range"});
    // The tester answers a byte per 90 ms, each byte inside libmodbus's byte timeout: only the
    // bound on the whole answer (0.5 s in the simulated lab's config) fails the reads, the
    // poller gives up after fault_tolerance_s and the run ends interrupted with the tester
    // named lost. The operator fixes the link and resumes the run.
    Cell slow{"tester slow",
              ph,
              false,
              [](Rig& r) { r.tester_proxy->slow(std::chrono::milliseconds(90)); },
              [](Rig& r) { r.tester_proxy->slow(std::chrono::milliseconds(0)); },
              "no complete answer within 500 ms"};
    slow.tester_via_proxy = true;
    out.push_back(slow);
    out.push_back({"vacuum seal loss", ph, true, [](Rig& r) { r.lab->inject_seal_loss(true); },
                   [](Rig& r) { r.lab->inject_seal_loss(false); },
                   ph == Phase::approach ? "vacuum did not reach 60 kPa" : "vacuum seal loss"});
  }
  // The OS refuses to grow the files (ulimit -f) from the start of step 2's approach: the
  // writes fail like on a full disk, the run ends interrupted, what was committed stays.
  // No event can say so (the file cannot take one): the engine's error does.
  Cell fsize{"file size limit", Phase::approach, false, [](Rig&) {}, nullptr, ""};
  fsize.file_size_limit = true;
  out.push_back(fsize);
  // A busy machine: two processes at normal priority burn both cores from step 2's approach
  // on; the pollers keep their rates, and no window is voided for missing readings.
  out.push_back(
      {"two busy processes", Phase::approach, false, [](Rig& r) { r.start_busy_processes(2); }, nullptr, ""});
  // The vacuum controller of the lab stops answering during a pin run, which does not use it:
  // events only, no window voided, no trip.
  Cell unused{"unused vacuum not answering",
              Phase::record,
              false,
              [](Rig& r) {
                r.lab->inject_vacuum_fault({ModbusFaultKind::no_reply, 1000000});
              },
              nullptr,
              "not used by this protocol"};
  unused.lab_vacuum = true;
  out.push_back(unused);
  // The file fills whenever it fills (a few pages after the start), in whatever phase.
  Cell storage{"storage full", Phase::approach, false,
               [](Rig&) {},    nullptr,         "storage: a database commit failed"};
  storage.storage = true;
  out.push_back(storage);
  return out;
}

}  // namespace

INSTANTIATE_TEST_SUITE_P(Cells, FaultMatrix, ::testing::ValuesIn(cells()), [](const auto& cell) {
  std::string n = cell.param.fault + "_" + name(cell.param.phase);
  for (auto& c : n)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return n;
});

// A damaged file (random bytes over a page) is refused when the engine's database is opened,
// before any instrument is opened or moved, and nothing is written into it.
TEST(FaultMatrixStorage, ADamagedDatabaseIsRefusedBeforeAnyInstrumentIsOpened) {
  const tocd::test::TempDir dir("faults_damaged");
  const fs::path path = dir / "runs.db";
  {
    tocd::db::Database db(path);
    const auto run = db.create_run({}).id;
    for (int i = 0; i < 3000; ++i)
      db.add_event({0, run, i, "note", fmt::format("event {} of a long run", i), -1, ""});
  }
  tocd::test::scribble_over_middle_page(path, 7);
  const auto size = fs::file_size(path);
  try {
    tocd::db::Database db(path);
    ADD_FAILURE() << "a damaged database was opened for writing";
  } catch (const tocd::db::DatabaseError& e) {
    EXPECT_NE(std::string(e.what()).find("is damaged (SQLite quick_check"), std::string::npos) << e.what();
  }
  EXPECT_EQ(fs::file_size(path), size);
  EXPECT_FALSE(fs::exists(path.string() + "-wal") && fs::file_size(path.string() + "-wal") > 0);
}
