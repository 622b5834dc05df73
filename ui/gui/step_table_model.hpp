#pragma once

#include <QAbstractTableModel>
#include <optional>
#include <vector>

namespace tocd::gui {

/// One row of the step table: a recorded step and, once it arrives, its prediction.
struct StepRow {
  int step = 0;  ///< step index within the run (0-based, as stored)
  double displacement_mm = 0;
  double nominal_strain = 0;
  double load_N = 0;
  double measured_T = 0;
  std::optional<double> predicted_T;
  std::optional<double> predicted_T_stderr;
  /// Seconds from the step's recording end to its prediction being stored; empty when the
  /// prediction was not made by its run (db::PredictionRecord::latency_s unset).
  std::optional<double> prediction_latency_s;

  /// (predicted - measured) / measured, when both exist and measured is not zero.
  std::optional<double> relative_difference() const;
};

/// The step table: displacement, nominal strain, load, measured T, predicted T, its
/// standard error, the relative difference and the prediction's latency, one row per step,
/// ordered by step index. Display text is formatted; Qt::UserRole gives the raw number (empty
/// when missing).
class StepTableModel : public QAbstractTableModel {
  Q_OBJECT

 public:
  enum Column {
    kStep,
    kDisplacement,
    kStrain,
    kLoad,
    kMeasuredT,
    kPredictedT,
    kPredictedErr,
    kDifference,
    kLatency,
    kColumnCount
  };

  explicit StepTableModel(QObject* parent = nullptr);

  int rowCount(const QModelIndex& parent = {}) const override;
  int columnCount(const QModelIndex& parent = {}) const override;
  QVariant data(const QModelIndex& index, int role = Qt::DisplayRole) const override;
  QVariant headerData(int section, Qt::Orientation orientation, int role = Qt::DisplayRole) const override;

  /// Adds the step or replaces its measured values (keeps a prediction already there).
  void upsert_measured(const StepRow& row);
  /// Sets the prediction of `step` (`latency_s` empty: not measured); a prediction for a step
  /// not yet listed is kept and shown once the step arrives (the two come from different
  /// threads).
  void set_prediction(int step, double T, double T_stderr, std::optional<double> latency_s = std::nullopt);
  void set_rows(std::vector<StepRow> rows);
  void clear();

  const std::vector<StepRow>& rows() const noexcept { return rows_; }
  /// The row of `step`, or nullptr.
  const StepRow* find(int step) const;
  int predicted_count() const;

 private:
  int row_of(int step) const;

  std::vector<StepRow> rows_;
  /// Predictions of steps not listed yet: rows holding only the step and its prediction.
  std::vector<StepRow> orphan_predictions_;
};

}  // namespace tocd::gui
