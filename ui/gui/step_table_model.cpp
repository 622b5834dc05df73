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
}};

bool is_column(int c) {
  return c >= 0 && c < StepTableModel::kColumnCount;
}

/// The row's number in `column` (empty when missing or no such column).
std::optional<double> column_value(const StepRow& r, int column) {
  if (!is_column(column)) return std::nullopt;
  return kColumns[static_cast<std::size_t>(column)].value(r);
}

}  // namespace

QVariant StepTableModel::headerData(int section, Qt::Orientation orientation, int role) const {
  if (role != Qt::DisplayRole || orientation != Qt::Horizontal || !is_column(section)) return {};
  return tr(kColumns[static_cast<std::size_t>(section)].header);
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
    const auto T = r.predicted_T, err = r.predicted_T_stderr;
    r = row;
    if (!r.predicted_T) {
      r.predicted_T = T;
      r.predicted_T_stderr = err;
    }
    emit dataChanged(index(i, 0), index(i, kColumnCount - 1));
    return;
  }
  const auto pos = std::lower_bound(rows_.begin(), rows_.end(), row.step,
                                    [](const StepRow& r, int s) { return r.step < s; });
  const int at = static_cast<int>(pos - rows_.begin());
  StepRow added = row;
  const auto orphan = std::find_if(orphan_predictions_.begin(), orphan_predictions_.end(),
                                   [&](const auto& o) { return o.first == row.step; });
  if (orphan != orphan_predictions_.end() && !added.predicted_T) {
    added.predicted_T = orphan->second.first;
    added.predicted_T_stderr = orphan->second.second;
    orphan_predictions_.erase(orphan);
  }
  beginInsertRows({}, at, at);
  rows_.insert(pos, added);
  endInsertRows();
}

void StepTableModel::set_prediction(int step, double T, double T_stderr) {
  const int i = row_of(step);
  if (i < 0) {
    orphan_predictions_.push_back({step, {T, T_stderr}});
    return;
  }
  StepRow& r = rows_[static_cast<std::size_t>(i)];
  r.predicted_T = T;
  r.predicted_T_stderr = T_stderr;
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
