#include "backend_study.hpp"

#include <QDir>
#include <chrono>
#include <cmath>
#include <future>

#include "background.hpp"

#if TOCD_GUI_WITH_STUDY
#include "tocd/analysis/sim_step_predictor.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/study/study.hpp"
#endif

namespace tocd::gui {

StudyBackend::StudyBackend(QObject* parent) : QObject(parent), tasks_(new TaskRunner(this, 1, true)) {}

StudyBackend::~StudyBackend() {
  tasks_->wait();
}

void StudyBackend::wait() {
  tasks_->wait();
}

bool StudyBackend::available() {
  return TOCD_GUI_WITH_STUDY != 0;
}

void StudyBackend::run_job(std::function<double()> work, const QString& action) {
  tasks_->run<double>(
      std::move(work),
      [this](double& seconds) {
        busy_ = false;
        emit finished(seconds);
      },
      [this, action](const QString& message) {
        busy_ = false;
        emit failed(action, message);
      });
}

#if TOCD_GUI_WITH_STUDY

namespace {

namespace study = tocd::sim::study;

SimulationRow row_of(const study::StudyRow& r) {
  SimulationRow s;
  s.id = r.c.id;
  s.label = QString::fromStdString(r.c.optics_label);
  s.displacement_mm = r.c.request.displacement_mm;
  s.thickness_mm = r.c.request.thickness_mm;
  s.strain = r.strain;
  s.T = r.p.T;
  s.T_stderr = r.p.T_stderr;
  s.rel_a = r.rel_a;
  s.rel_a_se = r.rel_a_se;
  s.seconds = r.seconds;
  if (r.p.fluence.is_object()) {
    s.horizontal_csv = QString::fromStdString(r.p.fluence.value("horizontal_csv", std::string()));
    s.vertical_csv = QString::fromStdString(r.p.fluence.value("vertical_csv", std::string()));
  }
  return s;
}

}  // namespace

void StudyBackend::run_study(qulonglong photons, const QString& fluence_dir) {
  if (busy_) return;
  busy_ = true;
  study::StudySettings settings;
  settings.photons = photons;
  settings.fluence_dir = fluence_dir.toStdString();
  if (!fluence_dir.isEmpty()) QDir().mkpath(fluence_dir);
  const auto cases = study::paper_cases(settings);
  const int total = static_cast<int>(cases.size());
  emit started(total);
  run_job(
      [this, settings, cases, total] {
        study::Predictor predictor(1);
        int done = 0;
        const auto t0 = std::chrono::steady_clock::now();
        study::run_study(predictor, cases, settings, 0, 3, [&](const study::StudyRow& r) {
          const SimulationRow row = row_of(r);
          const int d = ++done;
          QMetaObject::invokeMethod(
              this, [this, row, d, total] { emit row_done(row, d, total); }, Qt::QueuedConnection);
        });
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      },
      tr("Running the study"));
}

void StudyBackend::predict(double displacement_mm, double thickness_mm, const QString& optics,
                           qulonglong photons, const QString& fluence_dir) {
  if (busy_) return;
  busy_ = true;
  emit started(1);
  if (!fluence_dir.isEmpty()) QDir().mkpath(fluence_dir);
  run_job(
      [this, displacement_mm, thickness_mm, optics, photons, fluence_dir] {
        study::StudyCase c;
        c.id = 1;
        c.request.displacement_mm = displacement_mm;
        c.request.thickness_mm = thickness_mm;
        c.request.photons = photons;
        c.request.fluence_dir = fluence_dir.toStdString();
        c.request.fluence_stem = "prediction";
        study::apply_optics(optics.toStdString(), c.request, c.optics_label);
        study::validate(c.request);
        study::Predictor predictor(1);
        const auto t0 = std::chrono::steady_clock::now();
        study::StudyRow r;
        r.c = c;
        r.p = predictor.predict(c.request);
        r.strain = displacement_mm / thickness_mm;
        r.rel_a = r.rel_b = std::nan("");
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const SimulationRow row = row_of(r);
        QMetaObject::invokeMethod(
            this, [this, row] { emit row_done(row, 1, 1); }, Qt::QueuedConnection);
        return r.seconds;
      },
      tr("Predicting"));
}

std::shared_ptr<acquisition::StepPredictor> make_simulator_step_predictor(qulonglong photons) {
  // The same predictor as `tocdlab demo` / `run`: T relative to the glass-only geometry,
  // as the measured T is relative to the glass-only baseline power.
  analysis::SimPredictorSettings settings;
  settings.photons = photons;
  return analysis::make_recording_predictor(settings);
}

#else  // no simulator in this build

void StudyBackend::run_study(qulonglong, const QString&) {
  emit failed(tr("Running the study"), tr("this build of tocdlab has no simulator (sim/study)"));
}

void StudyBackend::predict(double, double, const QString&, qulonglong, const QString&) {
  emit failed(tr("Predicting"), tr("this build of tocdlab has no simulator (sim/study)"));
}

std::shared_ptr<acquisition::StepPredictor> make_simulator_step_predictor(qulonglong) {
  return nullptr;
}

#endif

}  // namespace tocd::gui
