#include "backend_run.hpp"

#include <QFileInfo>

#include "background.hpp"

namespace tocd::gui {

RunBackend::RunBackend(QObject* parent)
    : QObject(parent), tasks_(new TaskRunner(this)), waiter_(new TaskRunner(this)) {
  connect(&drain_timer_, &QTimer::timeout, this, &RunBackend::drain_samples);
  drain_timer_.setInterval(100);
}

RunBackend::~RunBackend() {
  tasks_->wait();
  if (engine_) engine_->abort("window closed");
  session_.reset();  // waits for the run's threads; no callback comes after this
  engine_ = nullptr;
  waiter_->wait();
  db_.reset();
}

void RunBackend::wait() {
  tasks_->wait();
  waiter_->wait();
}

void RunBackend::start(const acquisition::Protocol& protocol, const QString& db_path,
                       acquisition::InstrumentSet instruments, acquisition::EngineOptions options,
                       std::shared_ptr<acquisition::StepPredictor> predictor) {
  if (active_) {
    emit failed(tr("Starting a run"), tr("a run is already going"));
    return;
  }
  // A clock factor other than 1 is the simulated lab's: refuse one it cannot keep up with
  // before anything moves, naming the highest that works.
  if (options.clock_factor != 1.0) {
    try {
      acquisition::check_simulated_clock_factor(protocol, options.clock_factor);
    } catch (const std::exception& e) {
      emit failed(tr("Starting a run"), QString::fromUtf8(e.what()));
      return;
    }
  }
  release();
  active_ = true;
  db_path_ = db_path;
  {
    std::lock_guard lock(samples_mutex_);
    samples_.clear();
  }
  t0_ns_ = 0;
  struct Started {
    std::unique_ptr<db::Database> db;
    std::unique_ptr<acquisition::LabSession> session;
    std::int64_t run_id = 0;
  };
  auto inst = std::make_shared<acquisition::InstrumentSet>(std::move(instruments));
  const int step_count = static_cast<int>(protocol.steps.size());
  acquisition::EngineObserver* observer = this;  // a private base: convert here
  tasks_->run<std::shared_ptr<Started>>(
      [observer, protocol, db_path, inst, options, predictor] {
        auto s = std::make_shared<Started>();
        s->db = std::make_unique<db::Database>(db::Database::open(db_path.toStdString()));
        acquisition::LabSessionOptions so;
        so.engine = options;
        so.predictor = predictor;
        s->session = std::make_unique<acquisition::LabSession>(*s->db, std::move(*inst), so, observer);
        // Observer callbacks may already come from here on; they only touch the sample
        // buffer and queued calls, so they are safe before `engine_` is set.
        s->run_id = s->session->engine().start(protocol);
        return s;
      },
      [this, step_count](std::shared_ptr<Started>& s) {
        db_ = std::move(s->db);
        session_ = std::move(s->session);
        engine_ = &session_->engine();
        run_id_ = s->run_id;
        drain_timer_.start();
        emit started(run_id_, step_count);
        // The run may have ended before this arrived (a very short protocol).
        if (acquisition::is_terminal(engine_->state())) wait_for_end();
      },
      [this](const QString& message) {
        active_ = false;
        emit failed(tr("Starting the run"), message);
      });
}

void RunBackend::pause() {
  if (engine_) engine_->pause();
}
void RunBackend::resume() {
  if (engine_) engine_->resume();
}
void RunBackend::abort() {
  if (engine_) engine_->abort("operator abort (window)");
}

acquisition::EngineState RunBackend::state() const {
  return engine_ ? engine_->state() : acquisition::EngineState::idle;
}

void RunBackend::release() {
  if (active_) return;
  waiter_->wait();
  session_.reset();
  engine_ = nullptr;
  db_.reset();
}

void RunBackend::on_samples(std::span<const acquisition::LiveSample> samples) {
  std::lock_guard lock(samples_mutex_);
  if (t0_ns_ == 0 && !samples.empty()) t0_ns_ = samples.front().t_ns;
  const std::int64_t t0 = t0_ns_;
  for (const auto& s : samples) {
    samples_.push_back({s.channel, static_cast<double>(s.t_ns - t0) * 1e-9, s.value});
  }
}

void RunBackend::drain_samples() {
  std::vector<LiveReading> batch;
  {
    std::lock_guard lock(samples_mutex_);
    batch.swap(samples_);
  }
  if (!batch.empty()) emit live_readings(batch);
}

void RunBackend::on_step_recorded(const acquisition::StepResult& s) {
  const RecordedStepView v{s.index,          s.step_count, s.displacement_mm,
                           s.nominal_strain, s.load_N,     s.measured_T};
  QMetaObject::invokeMethod(
      this, [this, v] { emit step_recorded(v); }, Qt::QueuedConnection);
}

void RunBackend::on_prediction(int step_index, const acquisition::PredictedStep& p) {
  const double T = p.T, err = p.T_stderr, latency = p.latency_s;
  QMetaObject::invokeMethod(
      this, [this, step_index, T, err, latency] { emit prediction_arrived(step_index, T, err, latency); },
      Qt::QueuedConnection);
}

void RunBackend::on_event(const db::EventRecord& e) {
  const QString kind = QString::fromStdString(e.kind), message = QString::fromStdString(e.message);
  const int step = e.step_index;
  QMetaObject::invokeMethod(
      this, [this, kind, message, step] { emit event_recorded(kind, message, step); }, Qt::QueuedConnection);
}

void RunBackend::on_state(acquisition::EngineState state, const std::string& why) {
  const QString w = QString::fromStdString(why);
  QMetaObject::invokeMethod(
      this,
      [this, state, w] {
        emit state_changed(state, w);
        if (acquisition::is_terminal(state) && engine_) wait_for_end();
      },
      Qt::QueuedConnection);
}

void RunBackend::on_progress(const acquisition::Progress& p) {
  QMetaObject::invokeMethod(
      this, [this, p] { emit progress(p); }, Qt::QueuedConnection);
}

void RunBackend::wait_for_end() {
  if (waiting_ || !engine_) return;
  waiting_ = true;
  acquisition::Engine* engine = engine_;
  // wait() returns once every prediction has landed; engine_ stays alive meanwhile because
  // release() and the destructor wait for this task first.
  waiter_->run<acquisition::EngineState>([engine] { return engine->wait(); },
                                         [this, engine](acquisition::EngineState& final_state) {
                                           waiting_ = false;
                                           active_ = false;
                                           drain_timer_.stop();
                                           drain_samples();
                                           emit finished(final_state,
                                                         QString::fromStdString(engine->error()));
                                         },
                                         [this](const QString& message) {
                                           waiting_ = false;
                                           active_ = false;
                                           drain_timer_.stop();
                                           emit finished(acquisition::EngineState::failed, message);
                                         });
}

}  // namespace tocd::gui
