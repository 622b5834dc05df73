#pragma once

#include <QWidget>
#include <map>
#include <vector>

#include "backend_study.hpp"
#include "scalar_grid.hpp"

class QComboBox;
class QDoubleSpinBox;
class QHBoxLayout;
class QLabel;
class QProgressBar;
class QPushButton;
class QSpinBox;
class QTableWidget;
class QVBoxLayout;

namespace tocd::gui {

class FluenceMapPair;

/// The simulation view: photon budget, one prediction or the whole study, a progress bar,
/// the result table, and two fluence slices side by side on one log colour scale, for any
/// two simulations of the table (or both slices of one).
class SimulationView : public QWidget {
  Q_OBJECT

 public:
  explicit SimulationView(QWidget* parent = nullptr);

  qulonglong photons() const;
  void set_photons(qulonglong photons);
  double displacement_mm() const;
  double thickness_mm() const;
  QString optics() const;

  void begin(int total);
  void add_row(const SimulationRow& row, int done, int total);
  void finish(double seconds);
  void fail(const QString& message);

  /// Shows slice `slice` ("horizontal" or "vertical") of the simulations at table rows a, b.
  void show_maps(int row_a, int row_b, const QString& slice_a, const QString& slice_b);

  int row_count() const { return static_cast<int>(rows_.size()); }
  FluenceMapPair* maps() const noexcept { return maps_; }
  QProgressBar* progress_bar() const noexcept { return progress_; }

 signals:
  void predict_requested();
  void study_requested();

 private:
  // The constructor's parts, in the order it calls them.
  /// Ranges, steps and defaults of the prediction's inputs.
  void set_up_inputs();
  /// The inputs' form, the two buttons, the progress bar and the status line.
  QVBoxLayout* make_controls();
  void set_up_table();
  /// Which simulation and which slice each of the two maps shows.
  QHBoxLayout* make_map_pickers();
  void update_maps();

  QSpinBox* photons_;
  QDoubleSpinBox* displacement_;
  QDoubleSpinBox* thickness_;
  QComboBox* optics_;
  QPushButton* predict_button_;
  QPushButton* study_button_;
  QProgressBar* progress_;
  QLabel* status_;
  QTableWidget* table_;
  QComboBox* left_sim_;
  QComboBox* left_slice_;
  QComboBox* right_sim_;
  QComboBox* right_slice_;
  FluenceMapPair* maps_;
  std::vector<SimulationRow> rows_;
  std::map<QString, ScalarGrid> slice_cache_;  ///< slices already read, by path
};

}  // namespace tocd::gui
