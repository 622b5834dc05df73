#pragma once

#include <QDateTime>
#include <QObject>
#include <QPointF>
#include <QString>
#include <QVector>
#include <cstdint>
#include <memory>
#include <vector>

#include "step_table_model.hpp"
#include "tocd/db/reader.hpp"
#include "water_course_view.hpp"

namespace tocd::gui {

class TaskRunner;

/// A run as listed in the run browser.
struct RunListing {
  std::int64_t id = 0;
  QString uuid, name, status, operator_name;
  QDateTime started_utc;
  int steps = 0, predictions = 0, events = 0;
  bool live = false;
};

/// One event of a run, for the event log.
struct EventView {
  QDateTime utc;
  QString kind, message;
  int step = -1;
};

/// One channel's time series for display: (seconds since run start, value), decimated.
struct SeriesView {
  QString name, unit;
  std::vector<QPointF> points;
};

/// Everything the window shows of one stored run.
struct RunDetails {
  RunListing listing;
  std::vector<StepRow> rows;
  std::vector<EventView> events;
  std::vector<SeriesView> series;
  /// Load vs displacement, paired sample by sample where both channels were read together.
  std::vector<QPointF> load_vs_displacement;
};

/// A run's steps predicted with the sample's own law (analysis::compare_with_fitted_law).
struct FittedPoint {
  int step = 0;
  double nominal_strain = 0, T = 0, T_stderr = 0, band_lo = 0, band_hi = 0;
};
struct FittedLawView {
  std::int64_t run_id = 0;
  QString summary;  ///< the law, and where it came from, in one line
  std::vector<FittedPoint> points;
};

/// The step-table rows of a run (its compare rows): load is the step's mean of the channel
/// named "load" (or, failing that, the first channel in N).
std::vector<StepRow> step_rows(const std::vector<db::CompareRow>& compare,
                               const std::vector<db::Channel>& channels);
RunListing listing_of(const db::RunSummary& summary);
/// Reads one run for display; `max_points` bounds each chart's series.
RunDetails read_run_details(const db::Reader& reader, std::int64_t run_id, std::size_t max_points = 2000);

/// The run browser's link to a database file: opens it read-only (a db::Reader, so a run
/// recording into the same file is never blocked), lists runs, loads one, exports CSV. All
/// queries run on a worker thread; results and errors come back as signals on the GUI
/// thread. A corrupt or foreign file ends in failed(), never in a crash.
class RunBrowserBackend : public QObject {
  Q_OBJECT

 public:
  explicit RunBrowserBackend(QObject* parent = nullptr);
  ~RunBrowserBackend() override;

  void open_database(const QString& path);
  void refresh();
  void load_run(std::int64_t run_id);
  /// Writes the run's steps table as CSV (db::write_csv).
  void export_csv(std::int64_t run_id, const QString& path);
  /// Identifies the run's own law through the FE ("fitted") or takes it from a fit JSON
  /// (`tocdlab fit --method fe --json`), and re-predicts its steps with it and its confidence
  /// laws; or ("identified") identifies the whole sample and re-predicts with it. Minutes of work, on a
  /// worker of its own, so browsing goes on meanwhile; progress lines come as fit_progress(). Ignored while a
  /// fit is running.
  void fit_law(std::int64_t run_id, const QString& material = QStringLiteral("fitted"));
  bool fitting() const;
  /// Drives the biphasic FE along the run's recorded pin displacement and predicts T(t) at
  /// points in every hold (analysis::run_water_course), with each hold's measured T over
  /// time. About a minute per run at 20 000 photons; on the fit's worker, so one long job at a
  /// time (ignored while either runs); progress lines come as water_progress().
  void water_course(std::int64_t run_id, std::uint64_t photons = 20000);

  QString path() const { return path_; }
  bool is_open() const { return static_cast<bool>(reader_); }
  /// Blocks until queued work is done (tests, shutdown).
  void wait();

 signals:
  void database_opened(const QString& path, const QVector<tocd::gui::RunListing>& runs);
  void runs_listed(const QVector<tocd::gui::RunListing>& runs);
  void run_loaded(const tocd::gui::RunDetails& details);
  void exported(const QString& path);
  void fit_progress(const QString& line);
  void law_fitted(const tocd::gui::FittedLawView& view);
  void water_progress(const QString& line);
  void water_course_ready(const tocd::gui::WaterCourseView& view);
  void failed(const QString& action, const QString& message);

 private:
  TaskRunner* tasks_;
  TaskRunner* fits_;
  std::shared_ptr<db::Reader> reader_;
  QString path_;
};

}  // namespace tocd::gui
