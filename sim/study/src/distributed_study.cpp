// run_study across the members of a Team (MPI ranks). Member 0 runs a dispatcher thread that
// hands out units of work (a whole simulation, or a block of batches of a large one) to
// whichever member asks next, and sums the units' exact Monte Carlo tallies per simulation;
// every member, member 0 included, asks for units until none is left. The tallies of a
// simulation do not depend on which member ran which batches, so the table equals one
// process's in every number but the timings.
#include <algorithm>
#include <cstring>
#include <exception>
#include <thread>

#include <fmt/format.h>

#include "elapsed.hpp"
#include "table_builder.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/sim/study/study.hpp"

namespace tocd::sim::study {
namespace {

using parallel::Team;

// Tags: messages to member 0's dispatcher, and its answers to a worker.
constexpr int kToDispatcher = 1, kToWorker = 2;
// First word of a message to the dispatcher; the answer to kAsk is a unit index or kNoMoreWork.
constexpr std::int64_t kAsk = 0, kResult = 1, kNoMoreWork = -1;

struct Unit {
  std::size_t case_index = 0;
  int first_batch = 0, last_batch = 0;
};

std::vector<Unit> make_units(const std::vector<StudyCase>& cases, const StudySettings& settings,
                             int members) {
  std::vector<Unit> units;
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const PredictionRequest& r = cases[i].request;
    const int blocks = r.photons >= settings.split_photons ? std::min(members, r.batches) : 1;
    for (int k = 0; k < blocks; ++k)
      units.push_back({i, r.batches * k / blocks, r.batches * (k + 1) / blocks});
  }
  return units;
}

std::int64_t to_word(double x) {
  std::int64_t w = 0;
  std::memcpy(&w, &x, sizeof w);
  return w;
}

double from_word(std::int64_t w) {
  double x = 0;
  std::memcpy(&x, &w, sizeof x);
  return x;
}

// What member 0 gathers for one simulation.
struct CaseSum {
  mc::Tallies tallies;
  double seconds = 0;  // Monte Carlo time summed over the units
};

void dispatch(Team& team, const std::vector<Unit>& units, std::vector<CaseSum>& sums) {
  std::size_t next = 0, received = 0;
  int retired = 0;
  while (retired < team.size() || received < units.size()) {
    const Team::Message m = team.receive(-1, kToDispatcher);
    if (m.words.empty()) throw tocd::Error(fmt::format("empty work message from rank {}", m.source));
    if (m.words[0] == kAsk) {
      const std::int64_t answer = next < units.size() ? static_cast<std::int64_t>(next++) : kNoMoreWork;
      if (answer == kNoMoreWork) ++retired;
      team.send(m.source, kToWorker, std::span(&answer, 1));
      continue;
    }
    // kResult: unit, seconds, threads, tallies...
    if (m.words.size() < 4 || m.words[1] < 0 || static_cast<std::size_t>(m.words[1]) >= units.size())
      throw tocd::Error(fmt::format("malformed result message from rank {}", m.source));
    CaseSum& sum = sums[units[static_cast<std::size_t>(m.words[1])].case_index];
    const std::span<const std::int64_t> words(m.words.begin() + 4, m.words.end());
    if (sum.tallies.words.empty()) sum.tallies.words.assign(words.size(), 0);
    if (sum.tallies.words.size() != words.size())
      throw tocd::Error(fmt::format("rank {} sent {} tally words for a simulation of {}", m.source,
                                    words.size(), sum.tallies.words.size()));
    for (std::size_t i = 0; i < words.size(); ++i) sum.tallies.words[i] += words[i];
    sum.tallies.threads = std::max(sum.tallies.threads, static_cast<int>(m.words[3]));
    sum.seconds += from_word(m.words[2]);
    ++received;
  }
}

void work(Team& team, Predictor& predictor, const std::vector<StudyCase>& cases,
          const std::vector<Unit>& units) {
  for (;;) {
    team.send(0, kToDispatcher, std::span(&kAsk, 1));
    const Team::Message answer = team.receive(0, kToWorker);
    if (answer.words.size() != 1) throw tocd::Error("malformed work assignment from rank 0");
    if (answer.words[0] == kNoMoreWork) return;
    const Unit& u = units.at(static_cast<std::size_t>(answer.words[0]));
    const StudyRow row = TableBuilder::start_row(cases[u.case_index]);
    const auto t0 = Clock::now();
    const mc::Tallies t = predictor.run_batches(row.c.request, u.first_batch, u.last_batch);
    const double seconds = seconds_since(t0);
    std::vector<std::int64_t> message{kResult, answer.words[0], to_word(seconds), t.threads};
    message.insert(message.end(), t.words.begin(), t.words.end());
    team.send(0, kToDispatcher, message);
  }
}

}  // namespace

StudyTable run_study(Predictor& predictor, const std::vector<StudyCase>& cases, const StudySettings& settings,
                     int ref_a, int ref_b, const std::function<void(const StudyRow&)>& progress, Team& team) {
  if (team.size() == 1) return run_study(predictor, cases, settings, ref_a, ref_b, progress);
  const std::vector<Unit> units = make_units(cases, settings, team.size());
  std::vector<CaseSum> sums(cases.size());
  TableBuilder table(settings, ref_a, ref_b);

  std::thread dispatcher;
  if (team.rank() == 0) {
    dispatcher = std::thread([&] {
      try {
        dispatch(team, units, sums);
      } catch (const std::exception& e) {
        // The workers wait on this thread: end the whole job rather than leave them hanging.
        tocd::logger("study")->critical("study dispatcher: {}", e.what());
        team.abort(1);
      }
    });
  }
  try {
    work(team, predictor, cases, units);
  } catch (...) {
    // The caller ends the job (Team::abort); the dispatcher is ended with it.
    if (dispatcher.joinable()) dispatcher.detach();
    throw;
  }
  if (dispatcher.joinable()) dispatcher.join();
  // No member may start its next study while member 0's dispatcher still serves this one: it
  // would take the next study's requests for this one's.
  std::int64_t done = 1;
  team.sum(std::span(&done, 1));
  if (team.rank() != 0) return {};

  for (std::size_t i = 0; i < cases.size(); ++i) {
    StudyRow row = TableBuilder::start_row(cases[i]);
    row.p = predictor.assemble(row.c.request, sums[i].tallies, sums[i].seconds);
    row.seconds = sums[i].seconds;
    table.add(std::move(row), progress);
  }
  return table.finish();
}

}  // namespace tocd::sim::study
