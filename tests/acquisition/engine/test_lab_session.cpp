// The lab session wires instruments, database, predictor and engine for every caller; the
// demo protocol is protocols/demo.toml; wait() never blocks on a pause.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "engine_fixture.hpp"
#include "fake_rig.hpp"
#include "protocol_text.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/test/files.hpp"

using namespace tocd::acquisition;
using namespace tocd::acquisition::testing;
namespace fs = std::filesystem;

namespace {

class LabSessionTest : public EngineFixture {};

}  // namespace

TEST(DemoProtocol, IsTheFileInProtocols) {
  const std::string text = tocd::test::read_file(fs::path(TOCD_SOURCE_DIR) / "protocols" / "demo.toml");
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(std::string(demo_protocol_text()), text);
  const Protocol p = demo_protocol();
  ASSERT_EQ(p.steps.size(), 7u);
  EXPECT_DOUBLE_EQ(p.steps.front().displacement_mm, 0.0);
  EXPECT_DOUBLE_EQ(p.steps.back().displacement_mm, 1.5);
  EXPECT_EQ(p.kind, StepKind::displacement);
}

TEST_F(LabSessionTest, OpenInstrumentsRecordIntoTheDatabaseWithTheCallersPredictor) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  auto predictor = std::make_shared<FakePredictor>(1.02);
  tocd::db::Database db(dir_ / "runs.db");
  LabSessionOptions o;
  o.engine.clock_factor = kFactor;
  o.engine.lab_config_text = "# the rig of this test";
  o.predictor = predictor;
  std::int64_t run = 0;
  {
    LabSession session(db, make_fake_instruments(world), o);
    EXPECT_EQ(&session.database(), &db);
    run = session.engine().start(parse_protocol(pin_protocol("0.25, 0.5"), "session.toml"));
    EXPECT_EQ(session.engine().wait(), EngineState::completed) << session.engine().error();
  }
  const tocd::db::Reader r(dir_ / "runs.db");
  EXPECT_EQ(r.run(run).lab_config_text, "# the rig of this test");
  EXPECT_EQ(r.steps(run).size(), 2u);
  EXPECT_EQ(r.predictions(run).size(), 2u);  // every recorded pin step went to the predictor
  EXPECT_EQ(predictor->calls.load(), 2);
}

TEST_F(LabSessionTest, WaitHandsBackAPauseInsteadOfBlocking) {
  auto world = std::make_shared<FakeWorld>(kFactor);
  tocd::db::Database db(dir_ / "runs.db");
  LabSessionOptions o;
  o.engine.clock_factor = kFactor;
  LabSession session(db, make_fake_instruments(world), o);
  Engine& engine = session.engine();
  engine.start(parse_protocol(pin_protocol("0.25, 0.5"), "session.toml"));
  engine.pause();
  // Without the hand-back this wait would block for good: only this thread could resume.
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(engine.wait(), EngineState::paused);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 20.0);
  engine.resume();
  EXPECT_EQ(engine.wait(), EngineState::completed) << engine.error();
}
