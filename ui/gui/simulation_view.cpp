#include "simulation_view.hpp"

#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QProgressBar>
#include <QPushButton>
#include <QSpinBox>
#include <QSplitter>
#include <QTableWidget>
#include <QVBoxLayout>
#include <cmath>

#include "colour_map.hpp"
#include "slice_csv.hpp"

namespace tocd::gui {

namespace {
QString num(double v, int decimals) {
  return std::isfinite(v) ? QString::number(v, 'f', decimals) : QStringLiteral("—");
}
}  // namespace

SimulationView::SimulationView(QWidget* parent)
    : QWidget(parent),
      photons_(new QSpinBox(this)),
      displacement_(new QDoubleSpinBox(this)),
      thickness_(new QDoubleSpinBox(this)),
      optics_(new QComboBox(this)),
      predict_button_(new QPushButton(tr("Predict one step"), this)),
      study_button_(new QPushButton(tr("Run the study"), this)),
      progress_(new QProgressBar(this)),
      status_(new QLabel(this)),
      table_(new QTableWidget(this)),
      left_sim_(new QComboBox(this)),
      left_slice_(new QComboBox(this)),
      right_sim_(new QComboBox(this)),
      right_slice_(new QComboBox(this)),
      maps_(new FluenceMapPair(this)) {
  set_up_inputs();
  QVBoxLayout* controls = make_controls();
  set_up_table();
  QHBoxLayout* pick = make_map_pickers();

  auto* top = new QHBoxLayout();
  top->addLayout(controls);
  top->addWidget(table_, 1);
  auto* top_w = new QWidget(this);
  top_w->setLayout(top);
  auto* bottom = new QWidget(this);
  auto* bottom_col = new QVBoxLayout(bottom);
  bottom_col->addLayout(pick);
  bottom_col->addWidget(maps_, 1);
  auto* split = new QSplitter(Qt::Vertical, this);
  split->addWidget(top_w);
  split->addWidget(bottom);
  auto* col = new QVBoxLayout(this);
  col->addWidget(split);

  connect(predict_button_, &QPushButton::clicked, this, &SimulationView::predict_requested);
  connect(study_button_, &QPushButton::clicked, this, &SimulationView::study_requested);
  for (QComboBox* c : {left_sim_, left_slice_, right_sim_, right_slice_}) {
    connect(c, &QComboBox::currentIndexChanged, this, &SimulationView::update_maps);
  }
}

void SimulationView::set_up_inputs() {
  photons_->setRange(1000, 2000000000);
  photons_->setSingleStep(10000);
  photons_->setValue(100000);
  photons_->setGroupSeparatorShown(true);
  displacement_->setRange(0.0, 10.0);
  displacement_->setDecimals(3);
  displacement_->setSingleStep(0.1);
  displacement_->setValue(1.5);
  displacement_->setSuffix(QStringLiteral(" mm"));
  thickness_->setRange(0.1, 20.0);
  thickness_->setDecimals(3);
  thickness_->setValue(2.5);
  thickness_->setSuffix(QStringLiteral(" mm"));
  optics_->addItems({QStringLiteral("native"), QStringLiteral("cleared"), QStringLiteral("graded"),
                     QStringLiteral("a80"), QStringLiteral("s80"), QStringLiteral("n105")});
}

QVBoxLayout* SimulationView::make_controls() {
  auto* form = new QFormLayout();
  form->addRow(tr("Photons per simulation"), photons_);
  form->addRow(tr("Pin displacement"), displacement_);
  form->addRow(tr("Skin thickness"), thickness_);
  form->addRow(tr("Compressed-region optics"), optics_);
  auto* buttons = new QHBoxLayout();
  buttons->addWidget(predict_button_);
  buttons->addWidget(study_button_);
  auto* controls = new QVBoxLayout();
  controls->addLayout(form);
  controls->addLayout(buttons);
  controls->addWidget(progress_);
  controls->addWidget(status_);
  if (!StudyBackend::available()) {
    status_->setText(tr("This build has no simulator: predictions are not available."));
    predict_button_->setEnabled(false);
    study_button_->setEnabled(false);
  }
  return controls;
}

void SimulationView::set_up_table() {
  table_->setColumnCount(9);
  table_->setHorizontalHeaderLabels({tr("Sim"), tr("Optics"), tr("d (mm)"), tr("h (mm)"), tr("Strain"),
                                     tr("T"), tr("± s.e."), tr("T / glass"), tr("Time (s)")});
  table_->verticalHeader()->hide();
  table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  table_->horizontalHeader()->setStretchLastSection(true);
}

QHBoxLayout* SimulationView::make_map_pickers() {
  for (QComboBox* c : {left_slice_, right_slice_}) {
    c->addItem(tr("pin-tip height"), QStringLiteral("horizontal"));
    c->addItem(tr("pin axis"), QStringLiteral("vertical"));
  }
  right_slice_->setCurrentIndex(1);
  auto* pick = new QHBoxLayout();
  pick->addWidget(new QLabel(tr("Left:"), this));
  pick->addWidget(left_sim_);
  pick->addWidget(left_slice_);
  pick->addSpacing(20);
  pick->addWidget(new QLabel(tr("Right:"), this));
  pick->addWidget(right_sim_);
  pick->addWidget(right_slice_);
  pick->addStretch(1);
  return pick;
}

qulonglong SimulationView::photons() const {
  return static_cast<qulonglong>(photons_->value());
}
void SimulationView::set_photons(qulonglong photons) {
  photons_->setValue(static_cast<int>(std::min<qulonglong>(photons, 2000000000ULL)));
}
double SimulationView::displacement_mm() const {
  return displacement_->value();
}
double SimulationView::thickness_mm() const {
  return thickness_->value();
}
QString SimulationView::optics() const {
  return optics_->currentText();
}

void SimulationView::begin(int total) {
  rows_.clear();
  slice_cache_.clear();  // a new run rewrites the files
  table_->setRowCount(0);
  left_sim_->clear();
  right_sim_->clear();
  maps_->clear();
  progress_->setRange(0, total);
  progress_->setValue(0);
  progress_->setFormat(tr("%v of %m simulations"));
  status_->setText(tr("Simulating…"));
  predict_button_->setEnabled(false);
  study_button_->setEnabled(false);
}

void SimulationView::add_row(const SimulationRow& r, int done, int total) {
  rows_.push_back(r);
  const int i = table_->rowCount();
  table_->insertRow(i);
  const QStringList cells = {QString::number(r.id),  r.label,          num(r.displacement_mm, 3),
                             num(r.thickness_mm, 3), num(r.strain, 3), num(r.T, 4),
                             num(r.T_stderr, 4),     num(r.rel_a, 3),  num(r.seconds, 1)};
  for (int c = 0; c < cells.size(); ++c) table_->setItem(i, c, new QTableWidgetItem(cells[c]));
  const QString name = tr("%1: %2, d = %3 mm").arg(r.id).arg(r.label).arg(r.displacement_mm);
  {
    const QSignalBlocker a(left_sim_), b(right_sim_);
    left_sim_->addItem(name);
    right_sim_->addItem(name);
  }
  progress_->setRange(0, total);
  progress_->setValue(done);
  // Default view: the first simulation on the left, the latest on the right.
  left_sim_->setCurrentIndex(0);
  right_sim_->setCurrentIndex(right_sim_->count() - 1);
  update_maps();
}

void SimulationView::finish(double seconds) {
  status_->setText(tr("Done in %1 s").arg(seconds, 0, 'f', 1));
  predict_button_->setEnabled(true);
  study_button_->setEnabled(true);
}

void SimulationView::fail(const QString& message) {
  status_->setText(tr("Failed: %1").arg(message));
  predict_button_->setEnabled(StudyBackend::available());
  study_button_->setEnabled(StudyBackend::available());
}

void SimulationView::show_maps(int row_a, int row_b, const QString& slice_a, const QString& slice_b) {
  const auto pick = [](QComboBox* c, const QString& data) { c->setCurrentIndex(c->findData(data)); };
  const QSignalBlocker a(left_sim_), b(right_sim_), c(left_slice_), d(right_slice_);
  left_sim_->setCurrentIndex(row_a);
  right_sim_->setCurrentIndex(row_b);
  pick(left_slice_, slice_a);
  pick(right_slice_, slice_b);
  update_maps();
}

void SimulationView::update_maps() {
  const auto load = [this](QComboBox* sim, QComboBox* slice) -> ScalarGrid {
    const int i = sim->currentIndex();
    if (i < 0 || i >= static_cast<int>(rows_.size())) return {};
    const SimulationRow& r = rows_[static_cast<std::size_t>(i)];
    const bool horizontal = slice->currentData().toString() == QLatin1String("horizontal");
    const QString path = horizontal ? r.horizontal_csv : r.vertical_csv;
    if (path.isEmpty()) return {};
    try {
      auto cached = slice_cache_.find(path);
      if (cached == slice_cache_.end()) cached = slice_cache_.emplace(path, read_slice_csv(path)).first;
      ScalarGrid g = cached->second;
      g.title = tr("sim %1 (%2), %3").arg(r.id).arg(r.label, slice->currentText());
      return g;
    } catch (const SliceCsvError& e) {
      status_->setText(QString::fromUtf8(e.what()));
      return {};
    }
  };
  maps_->set_maps(load(left_sim_, left_slice_), load(right_sim_, right_slice_));
}

}  // namespace tocd::gui
