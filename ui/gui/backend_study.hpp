#pragma once

#include <QObject>
#include <QString>
#include <atomic>
#include <functional>
#include <memory>

#include "tocd/acquisition/step_predictor.hpp"

namespace tocd::gui {

class TaskRunner;

/// One finished simulation, as the result table shows it.
struct SimulationRow {
  int id = 0;
  QString label;  ///< optics label ("native", "glass only", ...)
  double displacement_mm = 0, thickness_mm = 0, strain = 0;
  double T = 0, T_stderr = 0;
  double rel_a = 0, rel_a_se = 0;  ///< T relative to the glass-only baseline (NaN: none)
  double seconds = 0;
  QString horizontal_csv, vertical_csv;  ///< fluence slices (pin-tip height, pin axis)
};

/// Runs the simulator for the simulation view: the published parametric study, or one
/// prediction, with a photon budget, on a worker thread; rows arrive one by one so a progress
/// bar can follow. Fluence slices are written as CSV into a folder of the caller's choice.
/// Built over sim::study; where the build has no simulator, available() is false and every
/// request ends in failed().
class StudyBackend : public QObject {
  Q_OBJECT

 public:
  explicit StudyBackend(QObject* parent = nullptr);
  ~StudyBackend() override;

  static bool available();

  /// The published study (baseline + native + optics variants); `total` rows.
  void run_study(qulonglong photons, const QString& fluence_dir);
  /// One prediction of a pin step.
  void predict(double displacement_mm, double thickness_mm, const QString& optics, qulonglong photons,
               const QString& fluence_dir);
  bool busy() const noexcept { return busy_; }
  void wait();

 signals:
  void started(int total);
  void row_done(const tocd::gui::SimulationRow& row, int done, int total);
  void finished(double seconds);
  void failed(const QString& action, const QString& message);

 private:
  /// Runs `work` (which returns its wall seconds) on the worker; either way the backend is
  /// free again before finished() or failed(action, ...) is emitted.
  void run_job(std::function<double()> work, const QString& action);

  TaskRunner* tasks_;
  bool busy_ = false;
};

/// The run engine's step predictor over the simulator with `photons` per step (null where
/// the build has no simulator: runs then record without predictions).
std::shared_ptr<acquisition::StepPredictor> make_simulator_step_predictor(qulonglong photons);

}  // namespace tocd::gui
