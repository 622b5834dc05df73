#pragma once

#include <QObject>
#include <QString>
#include <QTimer>
#include <atomic>
#include <memory>
#include <mutex>
#include <string_view>
#include <vector>

#include "tocd/acquisition/engine.hpp"
#include "tocd/acquisition/lab_session.hpp"
#include "tocd/db/database.hpp"

namespace tocd::gui {

class TaskRunner;

/// A live reading for the charts (seconds since the run started).
struct LiveReading {
  std::string_view channel;  ///< the run's channel, as its driver's capability table names it
  double t_s = 0;
  double value = 0;
};

/// A step as the step table and comparison chart show it.
struct RecordedStepView {
  int index = 0, step_count = 0;
  double displacement_mm = 0, nominal_strain = 0, load_N = 0, measured_T = 0;
};

/// The window's handle on one acquisition run: opens the database, builds the Engine with
/// the lab's instruments and the step predictor, and turns the EngineObserver callbacks
/// (engine threads) into signals on the GUI thread. Live samples are buffered under a mutex
/// and handed over in batches at ~10 Hz, so a 1 kHz stream costs ten queued calls a second,
/// not a thousand. Starting (which may measure a baseline) and waiting for the last
/// predictions run off the GUI thread.
class RunBackend : public QObject, private acquisition::EngineObserver {
  Q_OBJECT

 public:
  explicit RunBackend(QObject* parent = nullptr);
  ~RunBackend() override;

  /// Starts `protocol` against `instruments`, recording into the database at `db_path`
  /// (created when absent). Errors (bad protocol, bad database, missing instrument, zero
  /// baseline) end in failed() and give nothing back: the instruments are closed.
  void start(const acquisition::Protocol& protocol, const QString& db_path,
             acquisition::InstrumentSet instruments, acquisition::EngineOptions options,
             std::shared_ptr<acquisition::StepPredictor> predictor);

  void pause();
  void resume();
  void abort();

  bool is_active() const noexcept { return active_; }
  std::int64_t run_id() const noexcept { return run_id_; }
  QString database_path() const { return db_path_; }
  acquisition::EngineState state() const;
  /// The engine while a run exists (tests read its state); null otherwise.
  acquisition::Engine* engine() const noexcept { return engine_; }
  /// Drops the finished run's engine and database handle (before a new run).
  void release();
  void wait();

 signals:
  void started(qint64 run_id, int step_count);
  void live_readings(const std::vector<tocd::gui::LiveReading>& readings);
  void step_recorded(const tocd::gui::RecordedStepView& step);
  /// `latency_s`: seconds from the step's recording end to the prediction being stored.
  void prediction_arrived(int step_index, double T, double T_stderr, double latency_s);
  void event_recorded(const QString& kind, const QString& message, int step_index);
  void state_changed(tocd::acquisition::EngineState state, const QString& why);
  void progress(const tocd::acquisition::Progress& progress);
  /// The run ended and every prediction has landed (or failed).
  void finished(tocd::acquisition::EngineState state, const QString& error);
  void failed(const QString& action, const QString& message);

 private:
  // EngineObserver: engine threads.
  void on_samples(std::span<const acquisition::LiveSample> samples) override;
  void on_step_recorded(const acquisition::StepResult& step) override;
  void on_prediction(int step_index, const acquisition::PredictedStep& prediction) override;
  void on_event(const db::EventRecord& event) override;
  void on_state(acquisition::EngineState state, const std::string& why) override;
  void on_progress(const acquisition::Progress& progress) override;

  void drain_samples();
  void wait_for_end();

  TaskRunner* tasks_;
  TaskRunner* waiter_;
  std::unique_ptr<db::Database> db_;
  std::unique_ptr<acquisition::LabSession> session_;
  acquisition::Engine* engine_ = nullptr;  // session_'s engine
  QString db_path_;
  std::int64_t run_id_ = 0;
  bool active_ = false;
  bool waiting_ = false;
  std::atomic<std::int64_t> t0_ns_{0};

  std::mutex samples_mutex_;
  std::vector<LiveReading> samples_;  ///< guarded by samples_mutex_
  QTimer drain_timer_;
};

}  // namespace tocd::gui
