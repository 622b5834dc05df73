// Identification of simulated samples whose truth was drawn at random from the documented
// ranges (tocd/mocks/sample_truth.hpp): each sample is prepared (FE load curve, FE + Monte Carlo
// transmission), measured with the demo protocol through the simulated instruments' wire
// protocols into a database, and identified from the database alone. Every parameter the run
// determines must have a 95 % interval that covers the truth the sample was built with. The
// optical parameters are never reported as determined (their intervals are not calibrated;
// identify_optics.cpp): they are printed with their truth, for the record, and not counted.
//
// Default suite: three samples, the mechanics and the clearing's time course (the sample's
// tables at 4,000 photons; the optics' Monte Carlo, minutes per sample, is left to the long
// version); each determined parameter may miss its truth in at most one of the three (a
// calibrated 95 % interval misses twice or more in three with probability 0.7 %). With
// TOCD_IDENTIFY_LONG (physics-long): twenty samples at 50,000 photons with the optics (the
// sample's tables at 500,000), and each determined parameter may miss in at most 3 of them
// (more than 3 in 20: probability 1.6 %).
// The count is per parameter, never over parameters pooled: within one sample the stiffness,
// the overstress share and the relaxation time are correlated beyond 0.99 (short holds), so
// one unlucky noise draw moves all three together and their misses are not independent.
//
// The runs go at clock factor 2: at 5, on a loaded two-core machine, the tester's readings of a
// ramp arrive late enough to blur the relaxation history the mechanics rest on.
//
// Environment, for calibrating by hand: TOCD_IDENTIFY_SAMPLES (a count N, samples 1..N, or a
// list "5,6,18"; "5," is sample 5 alone), TOCD_IDENTIFY_THREADS (Monte Carlo threads, to share a
// machine between runs over different samples), TOCD_IDENTIFY_PROGRESS (progress on stderr).
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "tocd/acquisition/lab_session.hpp"
#include "tocd/analysis/identify_sample.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/mocks/default_sample.hpp"
#include "tocd/mocks/sample_truth.hpp"
#include "tocd/mocks/simulated_lab.hpp"
#include "tocd/test/simulated_run.hpp"
#include "tocd/test/temp_dir.hpp"

namespace fs = std::filesystem;
namespace a = tocd::analysis;
namespace acq = tocd::acquisition;
namespace mocks = tocd::mocks;

namespace {

// The sample's own transmission table is a Monte Carlo too, and its error is part of the
// sample that no identification can know: at the identification's photons it is as large as
// the model's own (0.9-1.2 % of T on sample 5, beside 0.8-1.6 %). The long version tabulates
// at ten times the photons, so that what the test calls the truth is known to a third of that.
// (It was not why the full clearing strain came out high in the first 20-sample run: sample 5
// re-identified on tables at 500,000 photons gave 0.444, on 50,000 0.443; docs/identify.md.)
#ifdef TOCD_IDENTIFY_LONG
constexpr int kSamples = 20;
constexpr std::uint64_t kPhotons = 50000;
constexpr std::uint64_t kSamplePhotons = 10 * kPhotons;
constexpr bool kOptics = true;
#else
constexpr int kSamples = 3;
constexpr std::uint64_t kPhotons = 4000;
constexpr std::uint64_t kSamplePhotons = kPhotons;  // the clearing's T_eq are free: no optics here
constexpr bool kOptics = false;
#endif

// TOCD_IDENTIFY_SAMPLES, when set, names the samples instead: a count N (samples 1..N) or a
// list "1,6,19". Twenty samples without the optics (the default binary) calibrate the
// mechanics and the clearing's time course in about 25 minutes; docs/identify.md.
std::vector<int> samples_to_identify() {
  std::vector<int> out;
  const char* env = std::getenv("TOCD_IDENTIFY_SAMPLES");
  const std::string text = env ? env : "";
  if (text.empty() || text.find(',') == std::string::npos) {
    const int n = text.empty() ? kSamples : std::stoi(text);
    for (int k = 1; k <= n; ++k) out.push_back(k);
    return out;
  }
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t comma = std::min(text.find(',', at), text.size());
    out.push_back(std::stoi(text.substr(at, comma - at)));
    at = comma + 1;
  }
  return out;
}

// At most this many misses per parameter among `samples` (20: 3, probability 1.6 % for a
// calibrated interval; 3: 1, 0.7 %).
int allowed_misses(std::size_t samples) {
  return samples >= 20 ? 3 : 1;
}

// The truth of each identified parameter, by the identification's names: the truth's own names
// (mocks::kSampleTruthFields), but for the relaxation's, which the identification calls g1 and tau1_s.
std::map<std::string, double> truth_by_name(const mocks::SampleTruth& t) {
  const std::map<std::string, std::string> identified_as{{"relaxation_fraction", "g1"},
                                                         {"relaxation_time_s", "tau1_s"}};
  std::map<std::string, double> out;
  for (const auto& f : mocks::kSampleTruthFields) {
    const auto renamed = identified_as.find(f.name);
    out[renamed == identified_as.end() ? std::string(f.name) : renamed->second] = t.*f.value;
  }
  return out;
}

// Records the demo protocol on a simulated lab with this truth; returns the run id.
std::int64_t record_demo(const fs::path& db_path, const mocks::SampleTruth& truth, std::uint64_t seed) {
  const acq::Protocol protocol = acq::demo_protocol();
  mocks::DefaultSampleOptions so;
  so.photons = kSamplePhotons;
  so.threads = 2;
  mocks::SimulatedLabOptions lo = mocks::simulated_lab_options(truth);
  lo.tissue = mocks::make_default_sample(protocol.sample.thickness_mm, 1.5, truth, so);
  lo.clock_factor = 2;
  lo.seed = seed;
  mocks::SimulatedLab lab(lo);
  const auto run = tocd::test::record_on_simulated_lab(db_path, lab, lo.clock_factor, protocol);
  EXPECT_EQ(run.end, acq::EngineState::completed);
  return run.id;
}

}  // namespace

TEST(IdentifySimulatedSamples, DeterminedParametersCoverTheDrawnTruth) {
  const tocd::test::TempDir dir("identify");
  std::map<std::string, int> determined, missed;
  const std::vector<int> samples = samples_to_identify();
  for (const int k : samples) {
    const mocks::SampleTruth truth = mocks::draw_sample_truth(static_cast<std::uint64_t>(k));
    const fs::path db = dir / fmt::format("sample{}.db", k);
    const std::int64_t run = record_demo(db, truth, static_cast<std::uint64_t>(k));
    a::SampleIdentificationOptions io;
    io.monte_carlo.photons = kPhotons;
    io.monte_carlo.seed = 1000 + static_cast<std::uint64_t>(k);
    // TOCD_IDENTIFY_THREADS: Monte Carlo threads, for sharing a machine between several runs
    // of this test over different samples (0, all cores, when unset).
    if (const char* threads = std::getenv("TOCD_IDENTIFY_THREADS"))
      io.monte_carlo.threads = std::atoi(threads);
    // TOCD_IDENTIFY_PROGRESS: the identification's progress lines on stderr, with the sample.
    if (std::getenv("TOCD_IDENTIFY_PROGRESS"))
      io.progress = [k](const std::string& line) {
        std::cerr << "sample " << k << ": " << line << std::endl;
      };
    io.optics = kOptics;
    const a::SampleIdentification id = a::identify_sample(tocd::db::Reader(db), run, io);
    ASSERT_TRUE(id.clearing) << "sample " << k;
    ASSERT_EQ(id.optics.has_value(), kOptics) << "sample " << k;
    const auto truths = truth_by_name(truth);
    std::vector<const a::ParameterReport*> reports{&id.mechanics.report, &id.clearing->report};
    if (id.optics) reports.push_back(&id.optics->report);
    for (const a::ParameterReport* rep : reports) {
      for (const auto& p : rep->parameters) {
        const auto t = truths.find(p.name);
        if (t == truths.end()) continue;
        const bool covered = p.lo <= t->second && t->second <= p.hi;
        // Undetermined parameters are printed for the calibration's record, not counted.
        if (p.determined) {
          ++determined[p.name];
          if (!covered) ++missed[p.name];
        }
        std::cout << fmt::format("sample {} {:<24} truth {:<9.5g} identified {:<9.5g} [{:.5g}, {:.5g}] {}\n",
                                 k, p.name, t->second, p.value, p.lo, p.hi,
                                 !p.determined ? "not determined"
                                 : covered     ? "covered"
                                               : "MISSED");
      }
    }
    // The optics' intervals are reported but never called determined (not calibrated).
    if (id.optics) {
      for (const auto& p : id.optics->report.parameters)
        EXPECT_FALSE(p.determined) << "sample " << k << " " << p.name;
    }
    // The mechanics are always determined by a demo run: stiffness and the relaxation.
    EXPECT_TRUE(id.mechanics.report.at("stiffness_scale").determined) << "sample " << k;
    EXPECT_TRUE(id.mechanics.report.at("g1").determined) << "sample " << k;
  }
  for (const auto& [name, count] : determined) {
    std::cout << fmt::format("{:<24} determined in {} of {} samples, missed {}\n", name, count,
                             samples.size(), missed[name]);
    EXPECT_LE(missed[name], allowed_misses(samples.size())) << name;
  }
}
