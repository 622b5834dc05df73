#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/protocol.hpp"
#include "tocd/acquisition/step_predictor.hpp"
#include "tocd/db/database.hpp"
#include "tocd/devices/lab.hpp"

namespace tocd::acquisition {

/// How a lab session records and predicts.
struct LabSessionOptions {
  /// Clock factor, operator, unattended, writer... `engine.lab_config_text` is stored with
  /// each run; left empty, the session stores the lab config it opened (as TOML).
  EngineOptions engine;
  /// Predicts T for every recorded step; null: no predictions (the front ends leave it null
  /// for vacuum protocols, which are never predicted). The front ends hand in the simulator's
  /// (analysis::make_recording_predictor); tests and other predictors hand in their own.
  std::shared_ptr<StepPredictor> predictor;
};

/// One run of the lab, wired the same way for `tocdlab run`, `tocdlab demo` and the GUI: the
/// instruments (opened from a lab config, or handed over already open), the measurement
/// database the run records into, the predictor of each recorded step, and the engine that
/// drives them. The simulated lab, when there is one, is the caller's: it only supplies the
/// lab config the session opens.
///
/// Destroying the session aborts a run still going and waits for it (Engine::~Engine).
class LabSession {
 public:
  /// Opens every instrument of `lab` (devices::open_lab). Throws the first DeviceError met.
  LabSession(db::Database& db, const devices::LabConfig& lab, LabSessionOptions options,
             EngineObserver* observer = nullptr);
  /// Instruments already open (the GUI's lab panel hands over its connections).
  LabSession(db::Database& db, InstrumentSet instruments, LabSessionOptions options,
             EngineObserver* observer = nullptr);
  LabSession(const LabSession&) = delete;
  LabSession& operator=(const LabSession&) = delete;

  Engine& engine() { return *engine_; }
  const Engine& engine() const { return *engine_; }
  db::Database& database() { return db_; }

 private:
  db::Database& db_;
  std::unique_ptr<Engine> engine_;
};

/// The instruments of an opened lab, as the engine takes them.
InstrumentSet to_instrument_set(devices::LabInstruments lab);

/// Most readings per real second the simulated lab's instruments are asked for. Measured on
/// an idle 2-core machine, the tester's Modbus twin served every reading up to about 12,000
/// per second (the demo protocol's 1000 Hz at --clock-factor 12) and 65 % of them at 20,000;
/// a third of that leaves room for a loaded machine and for sanitizer builds.
inline constexpr double kMaxSimulatedReadingsPerSecond = 5000.0;

/// The highest clock factor at which the simulated lab keeps `protocol`'s poll rates.
double max_simulated_clock_factor(const Protocol& protocol);

/// Throws ConfigError when `protocol` at `clock_factor` asks the simulated lab for more
/// readings per real second than kMaxSimulatedReadingsPerSecond, naming the highest clock
/// factor that works: a run that would lose recording windows is refused before it starts.
void check_simulated_clock_factor(const Protocol& protocol, double clock_factor);

/// The demo protocol (protocols/demo.toml, built in): seven pin-compression steps from contact
/// to 1.5 mm into a 2.5 mm sample. `tocdlab demo` and the GUI's demo run it.
std::string_view demo_protocol_text();
/// demo_protocol_text(), parsed.
Protocol demo_protocol();

}  // namespace tocd::acquisition
