// Every subcommand with --json writes exactly one valid JSON document on stdout (progress,
// messages and file names go to stderr), in the naming table of docs/cli.md: 1-based `step`,
// standard errors as NAME_se. Small inputs keep each case to seconds.
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tocd/test/cli.hpp"
#include "tocd/test/files.hpp"
#include "tocd/test/protocol_text.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
using tocd::test::run_cli;

namespace {

constexpr const char* kOptics = R"(ambient_n = 1.0
[region.1]
mu_a = 0.1
mu_s = 10.0
g = 0.9
n = 1.4
)";

// Two short compression steps on the simulated lab.
std::string two_step_protocol() {
  tocd::test::PinProtocolText p;
  p.name = "two steps";
  p.thickness_mm = 2.0;
  p.displacements_mm = "0.25, 0.5";
  return tocd::test::protocol_toml(p);
}

class CliJson : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(dir_ / "optics.toml") << kOptics;
    tocd::test::write_file(dir_ / "protocol.toml", two_step_protocol());
  }
  // Runs tocdlab and returns its stdout parsed as one JSON document; the test fails when the
  // exit status is not 0 or stdout holds anything besides that document.
  nlohmann::json json_of(const std::string& args) {
    const auto r = run_cli(TOCDLAB_EXE, args, dir_);
    EXPECT_EQ(r.status, 0) << "tocdlab " << args << "\nstderr: " << r.err;
    try {
      return nlohmann::json::parse(r.out);  // throws on trailing text: exactly one document
    } catch (const nlohmann::json::exception& e) {
      ADD_FAILURE() << "tocdlab " << args << ": stdout is not one JSON document (" << e.what() << "):\n"
                    << r.out;
      return nullptr;
    }
  }

  tocd::test::TempDir dir_{"cli_json"};
};

}  // namespace

TEST_F(CliJson, Version) {
  const auto j = json_of("version --json");
  EXPECT_TRUE(j.contains("tocdlab"));
}

TEST_F(CliJson, MonteCarloEstimatesCarryTheSeSuffix) {
  const auto j = json_of("mc --slab 10x10x1 --slab-cells 4 --optics optics.toml --photons 2000 --json");
  ASSERT_TRUE(j.is_object());
  ASSERT_TRUE(j.contains("transmittance"));
  EXPECT_TRUE(j["transmittance"].is_number());
  EXPECT_TRUE(j["transmittance_se"].is_number());
  EXPECT_FALSE(j.dump().find("\"se\"") != std::string::npos) << "an estimate left as {mean, se}";
}

TEST_F(CliJson, FiniteElement) {
  const auto j = json_of("fe --displacement 0.2 --refine 0.5 --json");
  ASSERT_TRUE(j.contains("steps"));
  EXPECT_EQ(j["steps"].size(), 1u);
}

TEST_F(CliJson, FitReadsItsDataFromDataCsv) {
  // Neo-Hookean uniaxial compression, mu = 0.1 MPa: P = mu (lambda - lambda^-2), lambda = 1 - e.
  std::ofstream csv(dir_ / "ss.csv");
  csv << "strain,stress_MPa\n";
  for (double e = 0.02; e < 0.41; e += 0.02) {
    const double l = 1 - e;
    csv << e << ',' << 0.1 * (1 / (l * l) - l) << '\n';
  }
  csv.close();
  const auto j = json_of("fit --data ss.csv --model neo-hookean --json");
  ASSERT_TRUE(j.contains("parameters"));
  EXPECT_GT(j["r_squared"].get<double>(), 0.99);
}

TEST_F(CliJson, PowermeterList) {
  const auto j = json_of("powermeter list-usb --json");
  EXPECT_TRUE(j.contains("devices"));
}

TEST_F(CliJson, StudySweepIsAFlagAndWritesOutputFile) {
  const auto j =
      json_of("study sweep --displacements 0.5 --no-baseline --photons 500 --mesh fast --json -o table.csv");
  ASSERT_TRUE(j.is_object());
  EXPECT_TRUE(fs::exists(dir_ / "table.csv"));
  const std::string csv = tocd::test::read_file(dir_ / "table.csv");
  EXPECT_EQ(csv.find('\r'), std::string::npos);
  EXPECT_EQ(csv.find("_stderr"), std::string::npos);
}

TEST_F(CliJson, PredictStep) {
  const auto j = json_of("predict --displacement 0.5 --photons 500 --mesh fast --json");
  EXPECT_TRUE(j["T"].is_number());
  EXPECT_TRUE(j["T_se"].is_number());
}

// T over a hold with water-content optics. Under a pin held still, the water that has left
// the skin can only grow and the pin force can only relax: the hold is a consolidation.
TEST_F(CliJson, PredictWaterTimeCourse) {
  const auto j = json_of("predict --optics water --times 0,10 --photons 1000 --json");
  EXPECT_EQ(j["optics"], "water");
  ASSERT_EQ(j["points"].size(), 2u);
  const auto& a = j["points"][0];
  const auto& b = j["points"][1];
  EXPECT_EQ(a["time_s"], 0.0);
  EXPECT_EQ(b["time_s"], 10.0);
  for (const auto* p : {&a, &b}) {
    EXPECT_TRUE((*p)["T"].is_number());
    EXPECT_TRUE((*p)["T_se"].is_number()) << "standard errors are NAME_se";
  }
  EXPECT_GT(b["water_outflow_mm3"].get<double>(), a["water_outflow_mm3"].get<double>());
  EXPECT_LE(b["pin_force_N"].get<double>(), a["pin_force_N"].get<double>());
}

TEST_F(CliJson, RunAndCompareNumberStepsFromOne) {
  const auto run = json_of(
      "run protocol.toml --simulated --sample analytic --no-predict --clock-factor 20 --db lab.db --json");
  ASSERT_TRUE(run.contains("compare"));
  EXPECT_EQ(run["state"], "completed");
  ASSERT_EQ(run["compare"]["steps"].size(), 2u);
  EXPECT_EQ(run["compare"]["steps"][0]["step"], 1);
  EXPECT_EQ(run["compare"]["steps"][1]["step"], 2);
  EXPECT_TRUE(run["compare"]["steps"][0].contains("predicted_T_se"));
  const auto cmp = json_of("compare --db lab.db --run 1 --json");
  EXPECT_EQ(cmp["steps"][0]["step"], 1);
}

// A recorded run's holds through the biphasic FE: one document, each step's points inside
// its recording window, the measured T next to a predicted T or a reason, never both missing.
TEST_F(CliJson, CompareWaterTimeCourse) {
  json_of(
      "run protocol.toml --simulated --sample analytic --no-predict --clock-factor 20 --db lab.db --json");
  const auto j = json_of("compare --db lab.db --run 1 --optics water --photons 500 --json");
  EXPECT_EQ(j["run"], 1);
  EXPECT_EQ(j["optics"], "water");
  EXPECT_EQ(j["config"]["thickness_mm"], 2.0) << "the protocol's sample";
  ASSERT_EQ(j["steps"].size(), 2u);
  EXPECT_EQ(j["steps"][0]["step"], 1);
  for (const auto& s : j["steps"]) {
    const double from = s["window_s"][0], to = s["window_s"][1];
    ASSERT_GE(s["points"].size(), 1u);
    for (const auto& p : s["points"]) {
      EXPECT_GE(p["t_s"].get<double>(), from);
      EXPECT_LE(p["t_s"].get<double>(), to);
      EXPECT_TRUE(p["measured_T"].is_number());
      EXPECT_TRUE(p["measured_T_se"].is_number()) << "standard errors are NAME_se";
      if (p["computed"].get<bool>()) {
        EXPECT_TRUE(p["predicted_T"].is_number());
        EXPECT_TRUE(p["predicted_T_se"].is_number());
      } else {
        EXPECT_FALSE(p["failure"].get<std::string>().empty());
        EXPECT_FALSE(p.contains("predicted_T"));
      }
    }
  }
}

TEST_F(CliJson, DemoPrintsItsRunSummary) {
  const auto j = json_of(
      "demo --protocol protocol.toml --photons 500 --sample-photons 500 --clock-factor 20 --cache-dir cache "
      "--identify-photons 1000 --db demo.db -o demo.csv --json");
  ASSERT_TRUE(j.contains("files"));
  EXPECT_EQ(j["files"]["csv"], "demo.csv");
  EXPECT_EQ(j["compare"]["steps"].size(), 2u);
  EXPECT_TRUE(j["compare"]["steps"][1]["predicted_T"].is_number());
  EXPECT_TRUE(fs::exists(dir_ / "demo.csv"));
  // The identified sample of the recorded run rides in the same document (docs/identify.md).
  ASSERT_TRUE(j.contains("identified"));
  EXPECT_EQ(j["identified"]["run"], j["run_id"]);
  EXPECT_TRUE(j["identified"]["mechanics"].is_object());
  EXPECT_TRUE(j["identified"]["clearing"].is_object());
  // Two held steps cannot give the four optical parameters: said, not thrown.
  EXPECT_TRUE(j["identified"]["optics"].is_null());
  EXPECT_TRUE(j["identified"].contains("optics_not_identified"));
  // Beside it, the identification held against the demo sample's truth (the default sample's
  // stiffness scale 1.25): without the optics there are no steps to re-predict.
  ASSERT_TRUE(j.contains("truth_check"));
  EXPECT_EQ(j["truth_check"]["parameters"][0]["name"], "stiffness_scale");
  EXPECT_EQ(j["truth_check"]["parameters"][0]["truth"], 1.25);
  EXPECT_EQ(j["truth_check"]["parameters"][0]["identified"],
            j["identified"]["mechanics"]["parameters"][1]["value"]);
  EXPECT_TRUE(j["truth_check"]["steps"].empty());
}

namespace {

// `tocdlab simlab` in the background for the instrument commands, stopped however the test
// ends. Its lab config names the ports it serves on.
class SimlabProcess {
 public:
  explicit SimlabProcess(const fs::path& dir) : dir_(dir) {
    const std::string cmd = fmt::format(
        "cd '{}' || exit 1; '{}' simlab --sample analytic --write-config lab.toml < /dev/null > simlab.log "
        "2>&1 & echo $! > "
        "simlab.pid",
        dir.string(), TOCDLAB_EXE);
    if (std::system(cmd.c_str()) != 0) return;
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (tocd::test::read_file(dir / "simlab.log").find("serving until") == std::string::npos) {
      if (std::chrono::steady_clock::now() > until) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    pid_ = std::stoi(tocd::test::read_file(dir / "simlab.pid"));
  }
  ~SimlabProcess() {
    if (pid_ > 0) ::kill(pid_, SIGTERM);
  }
  bool serving() const { return pid_ > 0; }
  /// The power meter's TCP port from the written lab config.
  int meter_port() const {
    const std::string lab = tocd::test::read_file(dir_ / "lab.toml");
    std::smatch m;
    const std::regex port(R"(\[power_meter\][^\[]*port = (\d+))");
    return std::regex_search(lab, m, port) ? std::stoi(m[1]) : -1;
  }

 private:
  fs::path dir_;
  int pid_ = -1;
};

}  // namespace

TEST_F(CliJson, DevicesProbeAndPowermeterReadOnTheSimulatedLab) {
  const SimlabProcess simlab(dir_);
  ASSERT_TRUE(simlab.serving()) << tocd::test::read_file(dir_ / "simlab.log");
  const auto probe = json_of("devices probe --lab lab.toml --json");
  for (const char* instrument : {"tester", "power_meter", "vacuum"}) {
    ASSERT_TRUE(probe.contains(instrument)) << probe.dump(2);
    EXPECT_TRUE(probe[instrument].contains("identity")) << probe[instrument].dump(2);
  }
  const int port = simlab.meter_port();
  ASSERT_GT(port, 0);
  const auto read = json_of(fmt::format("powermeter read --tcp 127.0.0.1:{} --json", port));
  for (const char* key : {"vendor", "model", "serial", "sensor", "power_W"})
    ASSERT_TRUE(read.contains(key)) << key << " missing:\n" << read.dump(2);
  ASSERT_TRUE(read["power_W"].is_number()) << read.dump(2);
  // The simulated meter sees the source through the sample: a positive power below the 1 mW source.
  EXPECT_GT(read["power_W"].get<double>(), 0.0);
  EXPECT_LT(read["power_W"].get<double>(), 1.0e-3);
}

TEST_F(CliJson, StudySensitivityListsEveryVariantWithItsError) {
  const auto j = json_of("study sensitivity --displacement 0.5 --photons 2000 --batches 4 --json");
  ASSERT_TRUE(j.contains("rows")) << j.dump(2);
  ASSERT_GE(j["rows"].size(), 2u);
  for (const auto& row : j["rows"]) {
    EXPECT_TRUE(row.contains("dT_se")) << row.dump();
  }
}

TEST_F(CliJson, StudyPaperJsonIsWhatPlotStudyReads) {
  const auto j = json_of("study paper --photons 200 --batches 2 --mesh fast --max-edge 1.0 --json");
  ASSERT_TRUE(j.is_object());
  std::ofstream(dir_ / "paper.json") << j.dump();
  const auto plot =
      run_cli(TOCDLAB_EXE, "plot study paper.json --column T -o bars.svg", dir_, "QT_QPA_PLATFORM=offscreen");
  EXPECT_EQ(plot.status, 0) << plot.err;
  EXPECT_TRUE(fs::exists(dir_ / "bars.svg"));
  EXPECT_TRUE(plot.out.empty()) << "plot writes a file, not stdout: " << plot.out;
}
