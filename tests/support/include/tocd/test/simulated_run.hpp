#pragma once
// A run recorded on a simulated lab as `tocdlab run --simulated` records one: what the tests
// and benchmarks that analyse a real recording start from. Needs tocd_acquisition and tocd_mocks.
#include <cstdint>
#include <filesystem>

#include "tocd/acquisition/lab_session.hpp"
#include "tocd/db/database.hpp"
#include "tocd/mocks/simulated_lab.hpp"

namespace tocd::test {

struct SimulatedRun {
  std::int64_t id = 0;
  acquisition::EngineState end{};  ///< how the run ended
};

/// Records `protocol` on `lab`, whose clock runs `clock_factor` times real time, into the
/// database at `db_path`. Unattended: a fault ends the run instead of pausing it for nobody.
inline SimulatedRun record_on_simulated_lab(const std::filesystem::path& db_path, mocks::SimulatedLab& lab,
                                            double clock_factor, const acquisition::Protocol& protocol) {
  db::Database db(db_path);
  acquisition::LabSessionOptions session;
  session.engine.clock_factor = clock_factor;
  session.engine.unattended = true;
  acquisition::LabSession lab_session(db, lab.config(), session);
  SimulatedRun run;
  run.id = lab_session.engine().start(protocol);
  run.end = lab_session.engine().wait();
  return run;
}

}  // namespace tocd::test
