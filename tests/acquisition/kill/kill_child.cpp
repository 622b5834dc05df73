// Child process of the kill test: runs a long protocol on the fake rig at real speed and says
// "recording" on stdout once the first step records. The test kills it with SIGKILL.
#include <cstdio>
#include <iostream>

#include "fake_rig.hpp"
#include "protocol_text.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/db/database.hpp"

namespace {
struct Announce : tocd::acquisition::EngineObserver {
  void on_state(tocd::acquisition::EngineState s, const std::string&) override {
    if (s == tocd::acquisition::EngineState::recording) {
      std::cout << "recording" << std::endl;
    }
  }
};
}  // namespace

int main(int argc, char** argv) {
  using namespace tocd::acquisition;
  if (argc != 2) {
    std::cerr << "usage: acq_kill_child DB\n";
    return 2;
  }
  auto world = std::make_shared<testing::FakeWorld>(1.0);
  tocd::db::Database db(argv[1]);
  Announce announce;
  Engine engine(db, testing::make_fake_instruments(world), {}, nullptr, &announce);
  engine.start(parse_protocol(testing::pin_protocol("0.25, 0.5", 50.0, 30.0, 1000.0), "kill.toml"));
  engine.wait();
  return 0;
}
