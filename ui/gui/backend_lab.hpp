#pragma once

#include <QObject>
#include <QString>
#include <QVector>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "instrument_kinds.hpp"
#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/devices/lab.hpp"
#include "tocd/mocks/simulated_lab.hpp"

namespace tocd::gui {

class TaskRunner;

/// One reading for an instrument panel.
struct InstrumentReading {
  InstrumentKind kind = InstrumentKind::tester;
  // tester: position (mm) and load (N); power meter: power (W); vacuum: pressure (kPa).
  double value = 0, value2 = 0;
  bool fault = false;
  QString fault_text;
};

struct InstrumentIdentity {
  InstrumentKind kind = InstrumentKind::tester;
  QString vendor, model, serial, firmware;
};

/// The connected lab: either a lab TOML (real instruments) or the simulated lab started in
/// process. Connecting, and every driver call, happens off the GUI thread. While no run is
/// going, one poller thread reads each instrument a few times a second for the panels
/// (drivers are not thread-safe: only that thread touches them). A run takes the
/// instruments (the engine owns them while it runs) and hands the lab back afterwards,
/// which reconnects from the same config.
class LabBackend : public QObject {
  Q_OBJECT

 public:
  explicit LabBackend(QObject* parent = nullptr);
  ~LabBackend() override;

  /// Parses the lab TOML and connects (ConfigError / DeviceError end in failed()).
  void connect_lab_file(const QString& path);
  /// Starts the simulated instruments in process (simulated time runs `clock_factor` fast)
  /// and connects to them over their real protocols. Without options.tissue the lab holds the
  /// default sample `tocdlab demo` measures (tocd/mocks/default_sample.hpp; the first start
  /// prepares it, minutes; later ones read it from the cache), with the stiffness and clearing
  /// of `truth` (its relaxation and delayed clearing are the options').
  void connect_simulated(mocks::SimulatedLabOptions options, const mocks::SampleTruth& truth = {});
  void disconnect_lab();

  bool is_connected() const noexcept { return config_.has_value(); }
  bool is_simulated() const noexcept { return static_cast<bool>(simulated_); }
  /// The simulated lab (fault hooks for demos and tests); null for a real lab.
  mocks::SimulatedLab* simulated_lab() const noexcept { return simulated_.get(); }
  double clock_factor() const noexcept { return clock_factor_; }
  /// The lab config as TOML, stored with each run.
  QString config_text() const;
  QString lab_name() const;
  bool has(InstrumentKind kind) const;

  /// Stops the idle poller and gives the instruments to a run (blocks briefly for the poller
  /// thread to finish its read). Empty when not connected.
  acquisition::InstrumentSet take_instruments();
  /// After a run: reconnects from the same config (in the background) and resumes polling.
  void reconnect();

  /// Blocks until background work is done (tests, shutdown).
  void wait();

 signals:
  void connected(const QString& lab_name, const QVector<tocd::gui::InstrumentIdentity>& identities);
  void disconnected();
  void reading(const tocd::gui::InstrumentReading& reading);
  /// A driver call of the idle poller failed (the panel shows the connection as lost).
  void instrument_error(tocd::gui::InstrumentKind kind, const QString& message);
  void failed(const QString& action, const QString& message);

 private:
  struct Connected;
  void finish_connect(std::shared_ptr<Connected> c);
  void start_polling(std::shared_ptr<devices::LabInstruments> instruments);
  void stop_polling();

  TaskRunner* tasks_;
  std::optional<devices::LabConfig> config_;
  std::unique_ptr<mocks::SimulatedLab> simulated_;
  double clock_factor_ = 1.0;
  std::shared_ptr<devices::LabInstruments> instruments_;  ///< owned by the poller while it runs
  std::thread poller_;
  std::atomic<bool> stop_poller_{false};
};

}  // namespace tocd::gui
