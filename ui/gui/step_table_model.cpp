#include "step_table_model.hpp"

#include <QBrush>
#include <QColor>
#include <algorithm>
#include <array>
#include <cmath>

namespace tocd::gui {

std::optional<double> StepRow::relative_difference() const {
  if (!predicted_T || measured_T == 0.0 || !std::isfinite(measured_T)) return std::nullopt;
  return (*predicted_T - measured_T) / measured_T;
}

StepTableModel::StepTableModel(QObject* parent) : QAbstractTableModel(parent) {}

int StepTableModel::rowCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : static_cast<int>(rows_.size());
}

int StepTableModel::columnCount(const QModelIndex& parent) const {
  return parent.isValid() ? 0 : kColumnCount;
}

namespace {

/// One column of the table: its header and the row's number in it (empty when missing).
struct ColumnSpec {
  const char* header;  ///< translated in StepTableModel's context
  std::optional<double> (*value)(const StepRow&);
  const char* tooltip = nullptr;  ///< the header's, where its words need saying (translated)
};

// In StepTableModel::Column order.
const std::array<ColumnSpec, StepTableModel::kColumnCount> kColumns{{
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Step"),
     [](const StepRow& r) -> std::optional<double> { return r.step; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Displacement (mm)"),
     [](const StepRow& r) -> std::optional<double> { return r.displacement_mm; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Nominal strain"),
     [](const StepRow& r) -> std::optional<double> { return r.nominal_strain; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Load (N)"),
     [](const StepRow& r) -> std::optional<double> { return r.load_N; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Measured T"),
     [](const StepRow& r) -> std::optional<double> { return r.measured_T; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Predicted T"),
     [](const StepRow& r) { return r.predicted_T; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "± error"),
     [](const StepRow& r) { return r.predicted_T_stderr; }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Difference"),
     [](const StepRow& r) { return r.relative_difference(); }},
    {QT_TRANSLATE_NOOP("tocd::gui::StepTableModel", "Latency (s)"),
     [](const StepRow& r) { return r.prediction_latency_s; },
     QT_TRANSLATE_NOOP("tocd::gui::StepTableModel",
                       "Seconds from the step's recording end to its prediction being stored")},
}};

bool is_column(int c) {
  return c >= 0 && c < StepTableModel::kColumnCount;
}

/// The row's number in `column` (empty when missing or no such column).
std::optional<double> column_value(const StepRow& r, int column) {
  if (!is_column(column)) return std::nullopt;
  return kColumns[static_cast<std::size_t>(column)].value(r);
}

/// Gives `to` the prediction of `from`.
void copy_prediction(StepRow& to, const StepRow& from) {
  to.predicted_T = from.predicted_T;
  to.predicted_T_stderr = from.predicted_T_stderr;
  to.prediction_latency_s = from.prediction_latency_s;
}

}  // namespace

QVariant StepTableModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (orientation != Qt::Horizontal || !is_column(section)) return {};
  const ColumnSpec& column = kColumns[static_cast<std::size_t>(section)];
  if (role == Qt::DisplayRole) return tr(column.header);
  if (role == Qt::ToolTipRole && column.tooltip) return tr(column.tooltip);
  return {};
}

QVariant StepTableModel::data(const QModelIndex& index, int role) const {
  if (!index.isValid() || index.row() >= rowCount()) return {};
  const StepRow& r = rows_[static_cast<std::size_t>(index.row())];
  const std::optional<double> raw = column_value(r, index.column());
  if (role == Qt::UserRole) return raw ? QVariant(*raw) : QVariant();
  if (role == Qt::TextAlignmentRole) return QVariant(Qt::AlignRight | Qt::AlignVCenter);
  if (role == Qt::ForegroundRole && !raw) return QBrush(QColor(140, 140, 140));
  if (role != Qt::DisplayRole) return {};
  if (!raw) {
    // A prediction made outside its run has no latency: nothing is pending there.
    if (index.column() == kLatency && r.predicted_T) return {};
    return index.column() >= kPredictedT ? tr("pending") : QVariant();
  }
  switch (index.column()) {
    case kStep:
      return QString::number(r.step + 1);  // people count steps from 1
    case kDisplacement:
    case kStrain:
    case kLoad:
      return QString::number(*raw, 'f', 3);
    case kMeasuredT:
    case kPredictedT:
    case kPredictedErr:
      return QString::number(*raw, 'f', 4);
    case kDifference:
      return QStringLiteral("%1 %").arg(*raw * 100.0, 0, 'f', 1);
    case kLatency:
      return QString::number(*raw, 'f', 2);
    default:
      return {};
  }
}

int StepTableModel::row_of(int step) const {
  const auto it =
      std::find_if(rows_.begin(), rows_.end(), [step](const StepRow& r) { return r.step == step; });
  return it == rows_.end() ? -1 : static_cast<int>(it - rows_.begin());
}

const StepRow* StepTableModel::find(int step) const {
  const int i = row_of(step);
  return i < 0 ? nullptr : &rows_[static_cast<std::size_t>(i)];
}

void StepTableModel::upsert_measured(const StepRow& row) {
  const int i = row_of(row.step);
  if (i >= 0) {
    StepRow& r = rows_[static_cast<std::size_t>(i)];
    const StepRow before = r;
    r = row;
    if (!r.predicted_T) copy_prediction(r, before);
    emit dataChanged(index(i, 0), index(i, kColumnCount - 1));
    return;
  }
  const auto pos = std::lower_bound(rows_.begin(), rows_.end(), row.step,
                                    [](const StepRow& r, int s) { return r.step < s; });
  const int at = static_cast<int>(pos - rows_.begin());
  StepRow added = row;
  const auto orphan = std::find_if(orphan_predictions_.begin(), orphan_predictions_.end(),
                                   [&](const StepRow& o) { return o.step == row.step; });
  if (orphan != orphan_predictions_.end() && !added.predicted_T) {
    copy_prediction(added, *orphan);
    orphan_predictions_.erase(orphan);
  }
  beginInsertRows({}, at, at);
  rows_.insert(pos, added);
  endInsertRows();
}

void StepTableModel::set_prediction(int step, double T, double T_stderr, std::optional<double> latency_s) {
  StepRow predicted;
  predicted.step = step;
  predicted.predicted_T = T;
  predicted.predicted_T_stderr = T_stderr;
  predicted.prediction_latency_s = latency_s;
  const int i = row_of(step);
  if (i < 0) {
    orphan_predictions_.push_back(predicted);
    return;
  }
  copy_prediction(rows_[static_cast<std::size_t>(i)], predicted);
  emit dataChanged(index(i, kPredictedT), index(i, kColumnCount - 1));
}

void StepTableModel::set_rows(std::vector<StepRow> rows) {
  beginResetModel();
  rows_ = std::move(rows);
  std::sort(rows_.begin(), rows_.end(), [](const StepRow& a, const StepRow& b) { return a.step < b.step; });
  orphan_predictions_.clear();
  endResetModel();
}

void StepTableModel::clear() {
  set_rows({});
}

int StepTableModel::predicted_count() const {
  return static_cast<int>(
      std::count_if(rows_.begin(), rows_.end(), [](const StepRow& r) { return r.predicted_T; }));
}

}  // namespace tocd::gui
