// `tocdlab run / runs / compare / export` end to end on the simulated lab. The runs use
// `--sample analytic`: what is tested here (the engine, the commands, signals, files) does not
// depend on the sample, and the analytic stand-in is ready at once (the default simulated
// sample is prepared once by sample.default.prepare and measured by the demo tests).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tocd/db/reader.hpp"
#include "tocd/test/cli_test.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/protocol_text.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
extern char** environ;

// Named, not anonymous: gtest derives each TEST_F class (external linkage) from the fixture.
namespace cli_run_support {

using tocd::test::read_file;

std::string protocol(double record_s) {
  tocd::test::PinProtocolText p;
  p.name = "cli test";
  p.displacements_mm = "0.25, 0.5, 0.75";
  p.record_s = record_s;
  return tocd::test::protocol_toml(p);
}

class CliRun : public tocd::test::CliTest {
 protected:
  /// Starts tocdlab with `args` in the background, stdout and stderr both into out_path().
  pid_t spawn(const std::vector<std::string>& args) {
    std::vector<std::string> words{TOCDLAB_EXE};
    words.insert(words.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (auto& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    const std::string out = out_path().string();
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, words[0].c_str(), &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc == 0 ? pid : -1;
  }
  fs::path out_path() const { return dir_ / "spawned.out"; }
  /// How a spawned process ended after interrupt().
  struct Ended {
    bool exited = false;
    int status = -1;
    double seconds = 0;  ///< from the first signal to the end
    std::string said;    ///< what it printed
  };
  /// Sends `count` SIGINTs 100 ms apart to the spawned `pid` and waits for it to end.
  Ended interrupt(pid_t pid, int count) {
    const auto t0 = std::chrono::steady_clock::now();
    for (int k = 0; k < count; ++k) {
      if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
      ::kill(pid, SIGINT);
    }
    int st = 0;
    ::waitpid(pid, &st, 0);
    Ended e;
    e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    e.exited = WIFEXITED(st);
    e.status = e.exited ? WEXITSTATUS(st) : -1;
    e.said = read_file(out_path());
    return e;
  }
  /// Waits until the spawned process has printed `text` (true) or `seconds` have passed.
  /// `tocdlab run` of the protocol file `p` into `db` on the analytic simulated lab, the
  /// clock 5 x faster, without predictions. Returns the exit status.
  int record(const fs::path& p, const fs::path& db) {
    return tocdlab(fmt::format("run {} --simulated --sample analytic --clock-factor 5 --no-predict --db {}",
                               p.string(), db.string()));
  }

  /// The same run started in the background, returned 1.5 s into its first recording window.
  pid_t spawn_recording(const fs::path& p, const fs::path& db) {
    const pid_t pid = spawn({"run", p.string(), "--simulated", "--sample", "analytic", "--clock-factor", "5",
                             "--db", db.string(), "--no-predict"});
    if (pid > 0) {
      // Approach, settle and hold take ~0.5 s at 5 x.
      wait_for_output("recording into", 30.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    }
    return pid;
  }

  /// `tocdlab run` of the protocol file `p` on the analytic simulated lab with `options` is
  /// refused (exit 1) before anything is opened: stderr says `why`, and no database is created.
  void expect_run_refused(const fs::path& p, const std::string& options, const std::string& why) {
    const auto db = dir_ / "lab.db";
    EXPECT_EQ(tocdlab(fmt::format("run {} --simulated --sample analytic {} --db {}", p.string(), options,
                                  db.string())),
              1);
    EXPECT_NE(err_.find(why), std::string::npos) << err_;
    EXPECT_FALSE(fs::exists(db));
  }

  bool wait_for_output(const std::string& text, double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (read_file(out_path()).find(text) == std::string::npos) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return true;
  }
};

}  // namespace cli_run_support

using namespace cli_run_support;

TEST_F(CliRun, RunsCompareExportOnTheSimulatedLab) {
  const auto p = write("p.toml", protocol(1.0));
  const auto db = dir_ / "lab.db";
  ASSERT_EQ(
      tocdlab(fmt::format("run {} --simulated --sample analytic --clock-factor 20 --photons 3000 --db {}",
                          p.string(), db.string())),
      0)
      << err_;
  // Progress and how the run ended on stderr; the table on stdout.
  EXPECT_NE(err_.find("step 3/3 recorded"), std::string::npos) << err_;
  EXPECT_NE(err_.find("run 1 completed"), std::string::npos) << err_;
  EXPECT_NE(out_.find("measured T"), std::string::npos) << out_;
  // Each prediction's line says how long after its step's recording it was stored.
  std::size_t stored_lines = 0;
  for (auto at = err_.find("after its recording ended"); at != std::string::npos;
       at = err_.find("after its recording ended", at + 1))
    ++stored_lines;
  EXPECT_EQ(stored_lines, 3u) << err_;

  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1 --json", db.string())), 0) << err_;
  const auto j = nlohmann::json::parse(out_);
  ASSERT_EQ(j["steps"].size(), 3u);
  double previous_T = 0, previous_load = -1;
  for (const auto& s : j["steps"]) {
    // The simulated tissue clears and stiffens under compression: T and load rise step by step.
    EXPECT_GT(s["measured_T"].get<double>(), previous_T);
    EXPECT_GT(s["load_N"].get<double>(), previous_load);
    previous_T = s["measured_T"].get<double>();
    previous_load = s["load_N"].get<double>();
    // Every step predicted by the simulator (T relative to glass only, few photons here).
    ASSERT_FALSE(s["predicted_T"].is_null());
    EXPECT_GT(s["predicted_T"].get<double>(), 0.0);
    EXPECT_GT(s["predicted_T_se"].get<double>(), 0.0);
  }
  EXPECT_DOUBLE_EQ(j["steps"][1]["nominal_strain"].get<double>(), 0.2);

  ASSERT_EQ(tocdlab(fmt::format("runs --db {}", db.string())), 0) << err_;
  EXPECT_NE(out_.find("completed"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("export --db {} --run 1 --format csv", db.string())), 0) << err_;
  EXPECT_EQ(out_.rfind("step,", 0), 0u) << out_;
  EXPECT_EQ(std::count(out_.begin(), out_.end(), '\n'), 4);  // header + 3 steps
  ASSERT_EQ(tocdlab(fmt::format("export --db {} --run 1 --format json --max-points 10", db.string())), 0)
      << err_;
  ASSERT_TRUE(nlohmann::json::accept(out_));
  // The run's predictions carry their latency (predicted while it recorded).
  const auto exported = nlohmann::json::parse(out_);
  ASSERT_EQ(exported["predictions"].size(), 3u);
  for (const auto& prediction : exported["predictions"]) {
    ASSERT_TRUE(prediction["latency_s"].is_number()) << prediction.dump();
    EXPECT_GE(prediction["latency_s"].get<double>(), 0.0);
  }
}

TEST_F(CliRun, MalformedProtocolNamesLineAndKeyAndCreatesNothing) {
  auto text = protocol(1.0);
  text.replace(text.find("record_s = 1"), 12, "record_s = \"one\"");
  const auto p = write("bad.toml", text);
  expect_run_refused(p, "--no-predict", "bad.toml:13: [steps] record_s: must be a number");
}

TEST_F(CliRun, NotADatabaseIsRefusedAndLeftAlone) {
  const auto notdb = write("notes.db", "these are my notes, not a database\n");
  EXPECT_EQ(tocdlab(fmt::format("runs --db {}", notdb.string())), 1);
  EXPECT_NE(err_.find("error"), std::string::npos);
  EXPECT_EQ(read_file(notdb), "these are my notes, not a database\n");
  const auto p = write("p.toml", protocol(1.0));
  EXPECT_EQ(tocdlab(fmt::format("run {} --simulated --sample analytic --no-predict --db {}", p.string(),
                                notdb.string())),
            1);
  EXPECT_EQ(read_file(notdb), "these are my notes, not a database\n");
}

TEST_F(CliRun, SigintAbortsGracefullyAndTheRunResumes) {
  const auto p = write("p.toml", protocol(60.0));  // long recording windows
  const auto db = dir_ / "lab.db";
  const pid_t pid = spawn_recording(p, db);
  ASSERT_GT(pid, 0);
  const Ended end = interrupt(pid, 1);
  ASSERT_TRUE(end.exited) << end.said;
  EXPECT_EQ(end.status, 0) << end.said;
  EXPECT_NE(end.said.find("run 1 aborted; all data kept"), std::string::npos) << end.said;
  {
    const tocd::db::Reader r(db);
    EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::aborted);
    bool sigint = false;
    for (const auto& e : r.events(1)) sigint = sigint || e.message.find("abort: SIGINT") != std::string::npos;
    EXPECT_TRUE(sigint);
    EXPECT_GT(r.sample_count(r.channel(1, "load")->id), 100);
  }
  // --resume continues the same run; a shorter protocol is not needed: it redoes from step 1
  // at the clock of the other runs here (a faster one outruns a 200 Hz tester poller on a busy machine).
  ASSERT_EQ(tocdlab(fmt::format(
                "run --resume 1 --simulated --sample analytic --no-predict --clock-factor 20 --db {}",
                db.string())),
            0)
      << err_;
  EXPECT_NE(err_.find("run 1 completed"), std::string::npos) << err_;
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.runs().size(), 1u);
  EXPECT_EQ(r.steps(1).size(), 3u);
}

TEST_F(CliRun, AKilledRunIsShownInterruptedByEveryReaderWithoutWritingTheFile) {
  const auto p = write("p.toml", protocol(60.0));
  const auto db = dir_ / "lab.db";
  const pid_t pid = spawn_recording(p, db);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));

  ASSERT_EQ(tocdlab(fmt::format("runs --db {}", db.string())), 0) << err_;
  EXPECT_NE(out_.find("interrupted"), std::string::npos) << out_;
  EXPECT_EQ(out_.find("running"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1", db.string())), 0) << err_;
  EXPECT_NE(out_.find("(interrupted)"), std::string::npos) << out_;
  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1 --json", db.string())), 0) << err_;
  EXPECT_EQ(nlohmann::json::parse(out_)["run"]["status"], "interrupted") << out_;
  // The readers presented it; the file still says what the dead process left (the next
  // writer marks it).
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::running);
  EXPECT_EQ(r.shown_status(1), tocd::db::RunStatus::interrupted);
}

TEST_F(CliRun, ExitStatusIsNonZeroAndSaysHowManySamplesWereLostWhenTheFileCannotGrow) {
  const auto p = write("p.toml", protocol(60.0));
  const auto db = dir_ / "lab.db";
  // A 2 MiB file-size limit: the database cannot hold the run's samples. No `trap '' XFSZ`:
  // tocdlab ignores SIGXFSZ itself (it used to die of it: exit 153, the run left `running`,
  // no message), so writes past the limit fail as on a full disk.
  const int rc =
      tocdlab(fmt::format("run {} --simulated --sample analytic --clock-factor 20 --no-predict --db {}",
                          p.string(), db.string()),
              "ulimit -f 4096; ");
  EXPECT_EQ(rc, 1) << out_ << err_;
  EXPECT_NE(err_.find("sample(s) were lost and are not in"), std::string::npos) << err_;
  EXPECT_NE(err_.find("lost to failed database commits"), std::string::npos) << err_;
  EXPECT_NE(err_.find("storage: a database commit failed"), std::string::npos) << err_;
  EXPECT_NE(err_.find("Continue it with: tocdlab run --resume 1"), std::string::npos) << err_;
  const tocd::db::Reader r(db);
  // Every reader shows the run interrupted. The file says so too when the run's last update
  // found room; when the full file refused that commit as well (as it may, by where the
  // write-ahead log stood), it still says running, as a killed run's does, until the next writer.
  EXPECT_EQ(r.shown_status(1), tocd::db::RunStatus::interrupted);
  EXPECT_TRUE(r.run(1).status == tocd::db::RunStatus::interrupted ||
              r.run(1).status == tocd::db::RunStatus::running);
  EXPECT_GT(r.sample_count(r.channel(1, "load")->id), 1000);  // what was committed stays
}

// After the last step, predictions may run for minutes; Ctrl-C must stop them at once, not
// wait for them (it waited 31.6 s). The recording is whole, so the run stays completed and
// each step left unpredicted has an event saying why.
TEST_F(CliRun, SigintAfterTheLastStepCancelsThePredictionsAtOnce) {
  const auto p = write("p.toml", protocol(0.5));
  const auto db = dir_ / "lab.db";
  // 5 million photons a step: minutes of Monte Carlo on two cores.
  const pid_t pid = spawn({"run", p.string(), "--simulated", "--sample", "analytic", "--clock-factor", "5",
                           "--photons", "5000000", "--db", db.string()});
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_output("step 3/3 recorded", 120.0)) << read_file(out_path());
  ASSERT_TRUE(wait_for_output("run 1 (3 steps)", 1.0));
  const Ended end = interrupt(pid, 1);
  const std::string& said = end.said;
  ASSERT_TRUE(end.exited) << said;
  EXPECT_EQ(end.status, 0) << said;
  // The promise is 2 s; the bound leaves room for a loaded machine and sanitizer builds (the
  // figure itself is measured in the closing note, not here).
  EXPECT_LT(end.seconds, 10.0) << said;
  EXPECT_NE(said.find("run 1 completed"), std::string::npos) << said;
  EXPECT_NE(said.find("step prediction(s) cancelled by the abort"), std::string::npos) << said;
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::completed);
  EXPECT_EQ(r.steps(1).size(), 3u);
  int cancelled = 0;
  for (const auto& e : r.events(1))
    if (e.kind == "prediction" && e.message.find("not predicted: run aborted: SIGINT") != std::string::npos)
      ++cancelled;
  EXPECT_EQ(static_cast<std::size_t>(cancelled) + r.predictions(1).size(), 3u);
  EXPECT_GE(cancelled, 1);
}

// Two Ctrl-C during a step, with a prediction running: the pin stops where it is, the
// predictions stop, and the program ends at once (it took 19.9 s). The second signal's event
// names where the pin was left.
TEST_F(CliRun, TwoSigintsDuringAStepWithAPredictionRunningEndAtOnce) {
  const auto p = write("p.toml", protocol(30.0));  // long windows: the signals meet step 2
  const auto db = dir_ / "lab.db";
  const pid_t pid = spawn({"run", p.string(), "--simulated", "--sample", "analytic", "--clock-factor", "5",
                           "--photons", "5000000", "--db", db.string()});
  ASSERT_GT(pid, 0);
  ASSERT_TRUE(wait_for_output("step 1/3 recorded", 120.0)) << read_file(out_path());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // step 2 under way, step 1 predicting
  const Ended end = interrupt(pid, 2);
  const std::string& said = end.said;
  ASSERT_TRUE(end.exited) << said;
  EXPECT_EQ(end.status, 0) << said;
  EXPECT_LT(end.seconds, 10.0) << said;  // promised 0.5 s after the second; see the note for the figure
  EXPECT_NE(said.find("run 1 aborted"), std::string::npos) << said;
  const tocd::db::Reader r(db);
  EXPECT_EQ(r.run(1).status, tocd::db::RunStatus::aborted);
  bool left_at = false, not_predicted = false;
  for (const auto& e : r.events(1)) {
    left_at = left_at || e.message.find("stopped at once: the pin is left at") != std::string::npos;
    not_predicted =
        not_predicted || (e.kind == "prediction" && e.message.find("not predicted") != std::string::npos);
  }
  EXPECT_TRUE(left_at);
  EXPECT_TRUE(not_predicted);
}

// Photons fewer than the Monte Carlo batches: every prediction would fail; the run is refused
// before anything is opened, and no database is created.
TEST_F(CliRun, TooFewPhotonsForThePredictionsAreRefusedBeforeTheRun) {
  expect_run_refused(write("p.toml", protocol(1.0)), "--photons 5",
                     "photons must be at least the 20 Monte Carlo batches");
}

// Data that cannot be written is an error, never an exit 0 with an empty file.
TEST_F(CliRun, OutputOnAFullDiskIsAnErrorAndLeavesNoFile) {
  const auto p = write("p.toml", protocol(0.5));
  const auto db = dir_ / "lab.db";
  ASSERT_EQ(record(p, db), 0) << err_;
  for (const std::string& args :
       {fmt::format("runs --db {}", db.string()), fmt::format("export --db {} --run 1", db.string()),
        fmt::format("export --db {} --run 1 --format json", db.string())}) {
    const int rc = tocdlab(args + " > /dev/full");
    EXPECT_EQ(rc, 1) << args << ": " << err_;
    EXPECT_NE(err_.find("writing standard output failed"), std::string::npos) << args << ": " << err_;
    EXPECT_NE(err_.find("disk full?"), std::string::npos) << err_;
  }
  EXPECT_EQ(tocdlab(fmt::format("export --db {} --run 1 -o /dev/full", db.string())), 1);
  EXPECT_NE(err_.find("cannot write /dev/full (disk full?)"), std::string::npos) << err_;
  // A file past a size limit: the export fails and leaves neither the file nor its .part.
  const auto csv = dir_ / "samples.csv";
  const int rc =
      tocdlab(fmt::format("export --db {} --run 1 --table samples -o {}", db.string(), csv.string()),
              "ulimit -f 100; ");
  EXPECT_EQ(rc, 1) << err_;
  EXPECT_NE(err_.find("disk full?"), std::string::npos) << err_;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(fs::exists(csv.string() + ".part"));
}

// A damaged database is refused before anything moves, and left as it was: `run` moved the
// pin and then failed "database disk image is malformed", or recorded into the damaged file.
TEST_F(CliRun, ADamagedDatabaseIsRefusedBeforeAnythingMovesAndLeftAlone) {
  const auto p = write("p.toml", protocol(0.5));
  const auto db = dir_ / "lab.db";
  ASSERT_EQ(record(p, db), 0) << err_;
  ASSERT_GT(fs::file_size(db), 16u * 4096u);
  tocd::test::scribble_over_middle_page(db, 12345);
  const std::string before = read_file(db);
  EXPECT_EQ(record(p, db), 1);
  EXPECT_NE(err_.find("is damaged (SQLite quick_check"), std::string::npos) << err_;
  EXPECT_NE(err_.find("nothing was written to it"), std::string::npos) << err_;
  EXPECT_EQ(err_.find("recording into"), std::string::npos) << err_;  // no run was started
  EXPECT_EQ(read_file(db), before);
}

// A protocol's name is stored as written and may hold anything; the table `run` prints and
// `compare` show it without terminal controls (ESC) or bidirectional overrides (U+202E).
TEST_F(CliRun, ControlCharactersInAStoredNameNeverReachTheTerminal) {
  std::string text = protocol(0.5);
  text.replace(text.find("name = \"cli test\""), 17, R"(name = "red \u001B[31m then \u202Eevil")");
  const auto p = write("p.toml", text);
  const auto db = dir_ / "lab.db";
  ASSERT_EQ(record(p, db), 0) << err_;
  const auto clean = [](const std::string& s) {
    return s.find('\x1b') == std::string::npos && s.find("\xE2\x80\xAE") == std::string::npos;
  };
  // The database files at rest: the file and the run lock, no -wal or -shm (the writer closed).
  const auto db_files = [&] {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind("lab.db", 0) == 0) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> at_rest{"lab.db", "lab.db-runlock"};
  EXPECT_EQ(db_files(), at_rest);
  EXPECT_TRUE(clean(out_)) << out_;
  EXPECT_NE(out_.find("red \xEF\xBF\xBD[31m then \xEF\xBF\xBD"
                      "evil"),
            std::string::npos)
      << out_;
  ASSERT_EQ(tocdlab(fmt::format("compare --db {} --run 1", db.string())), 0) << err_;
  EXPECT_TRUE(clean(out_)) << out_;
  ASSERT_EQ(tocdlab(fmt::format("runs --db {}", db.string())), 0) << err_;
  EXPECT_TRUE(clean(out_)) << out_;
  ASSERT_EQ(tocdlab(fmt::format("runs --db {} --json", db.string())), 0) << err_;
  EXPECT_TRUE(clean(out_)) << out_;
  const auto listing = nlohmann::json::parse(out_);
  ASSERT_EQ(listing["runs"].size(), 1u);
  EXPECT_EQ(listing["runs"][0]["run_id"], 1);
  EXPECT_EQ(listing["runs"][0]["status"], "completed");
  EXPECT_EQ(listing["runs"][0]["steps"], 3);
  ASSERT_EQ(tocdlab(fmt::format("export --db {} --run 1", db.string())), 0) << err_;
  // Commands that only read leave the directory as they found it.
  EXPECT_EQ(db_files(), at_rest);
  // The database keeps the name as written.
  EXPECT_EQ(tocd::db::Reader(db).run(1).name,
            "red \x1b[31m then \xE2\x80\xAE"
            "evil");
}
