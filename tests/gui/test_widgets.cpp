#include <QChart>
#include <QComboBox>
#include <QLineSeries>
#include <QMainWindow>
#include <QPushButton>
#include <QTemporaryDir>
#include <QTest>
#include <QValueAxis>
#include <cmath>

#include "browser_view.hpp"
#include "colour_map.hpp"
#include "comparison_chart.hpp"
#include "event_log.hpp"
#include "gui_settings.hpp"
#include "hold_course_chart.hpp"
#include "instrument_panel.hpp"
#include "interlock_indicator.hpp"
#include "lab_view.hpp"
#include "live_chart.hpp"

using namespace tocd::gui;

class WidgetsTest : public QObject {
  Q_OBJECT

 private slots:
  void live_chart_decimates_a_1khz_stream();
  void live_chart_scrolls_a_time_window();
  void comparison_chart_fills_in();
  void comparison_chart_draws_a_fitted_law_with_two_bands();
  void browser_draws_a_fit_only_on_its_own_run();
  void hold_chart_draws_measured_T_and_predicted_points();
  void browser_shows_the_hold_of_the_chosen_step();
  void colour_map_shares_one_log_scale();
  void colour_map_orientation_and_no_data();
  void event_log_is_bounded();
  void instrument_panel_shows_state();
  void lab_view_lays_out_the_drivers_capability_tables();
  void interlock_indicator_states();
  void settings_round_trip();
};

void WidgetsTest::live_chart_decimates_a_1khz_stream() {
  LiveChart chart({QStringLiteral("load"), QStringLiteral("d"), QStringLiteral("F"), 0.05, 0.0, 100000});
  // 20 s of 1 kHz load vs displacement, with one spike that must survive decimation.
  double y_max = -1e9, y_min = 1e9;
  for (int i = 0; i < 20000; ++i) {
    const double t = i * 1e-3;
    const double d = 0.05 * t;
    double F = 2.0 * d * d + 0.01 * std::sin(i);
    if (i == 12345) F = 40.0;
    y_max = std::max(y_max, F);
    y_min = std::min(y_min, F);
    chart.add(t, d, F);
  }
  QVERIFY(chart.displayed_points().empty());  // nothing is drawn before the refresh tick
  chart.refresh();
  const auto pts = chart.displayed_points();
  QCOMPARE(chart.samples_seen(), std::size_t{20000});
  QVERIFY2(pts.size() <= 4 * 400, qPrintable(QString::number(pts.size())));
  QVERIFY(pts.size() >= 400);
  QVERIFY(std::any_of(pts.begin(), pts.end(), [](const QPointF& p) { return p.y() == 40.0; }));
  QVERIFY(chart.y_axis()->max() >= y_max);
  QVERIFY(chart.y_axis()->min() <= y_min);
  QVERIFY(chart.x_axis()->max() >= 0.05 * 19.999);
  chart.clear();
  QVERIFY(chart.displayed_points().empty());
}

void WidgetsTest::live_chart_scrolls_a_time_window() {
  LiveChart chart({QStringLiteral("power"), QStringLiteral("t"), QStringLiteral("P"), 0.1, 30.0, 100000});
  for (int i = 0; i < 1200; ++i) chart.add(i * 0.1, i * 0.1, 1e-3 * (1 + i % 3));  // 10 Hz, 120 s
  chart.refresh();
  const auto pts = chart.displayed_points();
  QVERIFY(!pts.empty());
  QVERIFY(pts.front().x() >= 119.9 - 30.0 - 1e-9);
  QCOMPARE(chart.x_axis()->max(), 119.9);
  QVERIFY(std::abs(chart.x_axis()->min() - 89.9) < 1e-9);
}

void WidgetsTest::comparison_chart_fills_in() {
  ComparisonChart chart;
  chart.set_measured(0, 0.1, 0.50);
  chart.set_measured(1, 0.2, 0.45);
  QCOMPARE(chart.measured_points().size(), std::size_t{2});
  QVERIFY(chart.predicted_points().empty());
  QVERIFY(chart.error_bars().empty());
  chart.set_predicted(1, 0.2, 0.47, 0.01);
  chart.set_predicted(0, 0.1, 0.52, -0.02);  // the sign of a standard error is meaningless
  QCOMPARE(chart.predicted_points().size(), std::size_t{2});
  const auto bars = chart.error_bars();
  QCOMPARE(bars.size(), std::size_t{2});
  QCOMPARE(bars[0].x, 0.1);
  QVERIFY(std::abs(bars[0].lo - 0.50) < 1e-12 && std::abs(bars[0].hi - 0.54) < 1e-12);
  QVERIFY(std::abs(bars[1].lo - 0.46) < 1e-12 && std::abs(bars[1].hi - 0.48) < 1e-12);
  // A step predicted again replaces its point.
  chart.set_predicted(1, 0.2, 0.40, 0.01);
  QCOMPARE(chart.predicted_points().size(), std::size_t{2});
  QCOMPARE(chart.predicted_points()[1].y(), 0.40);
  chart.clear();
  QVERIFY(chart.measured_points().empty());
  QVERIFY(chart.error_bars().empty());
}

void WidgetsTest::comparison_chart_draws_a_fitted_law_with_two_bands() {
  ComparisonChart chart;
  chart.set_measured(0, 0.2, 0.50);
  chart.set_predicted(0, 0.2, 0.46, 0.01);
  QVERIFY(chart.fitted_points().empty() && chart.model_bands().empty());
  chart.set_fitted(0, 0.2, 0.55, 0.012, 0.58, 0.53);  // band ends in either order
  chart.set_fitted(1, 0.4, 0.70, 0.02, 0.66, 0.75);
  QCOMPARE(chart.fitted_points().size(), std::size_t{2});
  QCOMPARE(chart.fitted_points()[0].y(), 0.55);
  const auto mc = chart.fitted_error_bars();
  const auto band = chart.model_bands();
  QCOMPARE(mc.size(), std::size_t{2});
  QCOMPARE(band.size(), std::size_t{2});
  QVERIFY(std::abs(mc[0].lo - 0.538) < 1e-12 && std::abs(mc[0].hi - 0.562) < 1e-12);
  QCOMPARE(band[0].x, 0.2);
  QCOMPARE(band[0].lo, 0.53);
  QCOMPARE(band[0].hi, 0.58);
  QCOMPARE(band[1].hi, 0.75);
  // The axis takes in the whole band.
  QVERIFY(chart.chart()->axes(Qt::Vertical).front()->property("max").toDouble() >= 0.75);
  // The stored predictions keep their own bars; clearing the fit leaves them.
  QCOMPARE(chart.error_bars().size(), std::size_t{1});
  chart.clear_fitted();
  QVERIFY(chart.fitted_points().empty() && chart.model_bands().empty() && chart.fitted_error_bars().empty());
  QCOMPARE(chart.predicted_points().size(), std::size_t{1});
}

void WidgetsTest::browser_draws_a_fit_only_on_its_own_run() {
  BrowserView view;
  RunDetails d;
  d.listing.id = 7;
  StepRow r;
  r.step = 0;
  r.nominal_strain = 0.2;
  r.measured_T = 0.5;
  d.rows.push_back(r);
  view.show_run(d);
  QVERIFY(view.fit_button()->isEnabled());
  QVERIFY(view.identify_button()->isEnabled());
  FittedLawView other;
  other.run_id = 8;
  other.points.push_back({0, 0.2, 0.6, 0.01, 0.55, 0.65});
  view.show_fitted(other);  // arrived after the user moved to run 7
  QVERIFY(view.comparison()->fitted_points().empty());
  FittedLawView mine = other;
  mine.run_id = 7;
  mine.summary = QStringLiteral("published law x 1.6");
  view.set_fitting(true);
  QVERIFY(!view.fit_button()->isEnabled());
  QVERIFY(!view.identify_button()->isEnabled());  // one long job at a time
  view.set_fitting(false);
  QVERIFY(view.identify_button()->isEnabled());
  view.show_fitted(mine);
  QCOMPARE(view.comparison()->fitted_points().size(), std::size_t{1});
  QVERIFY(view.fit_text().contains(QStringLiteral("x 1.6")));
  // Reloading the same run keeps its fit; another run drops it.
  view.show_run(d);
  QCOMPARE(view.comparison()->model_bands().size(), std::size_t{1});
  d.listing.id = 9;
  view.show_run(d);
  QVERIFY(view.comparison()->fitted_points().empty());
  QVERIFY(view.fit_text().isEmpty());
}

namespace {
// Two holds: the first with two computed points, the second where the solver stopped.
WaterCourseView water_course(std::int64_t run_id) {
  WaterCourseView v;
  v.run_id = run_id;
  v.summary = QStringLiteral("water optics, 500 photons per point");
  WaterStepView a;
  a.step = 0;
  a.displacement_mm = 0.25;
  a.window_from_s = 10;
  a.window_to_s = 15;
  for (int i = 0; i <= 50; ++i) a.measured.emplace_back(10 + 0.1 * i, 0.20 + 0.001 * i);
  a.points.push_back({10.5, 0.2, true, 0.18, 0.004, {}});
  a.points.push_back({14.5, 0.24, true, 0.19, 0.005, {}});
  WaterStepView b;
  b.step = 1;
  b.displacement_mm = 1.0;
  b.window_from_s = 20;
  b.window_to_s = 25;
  b.measured = {{20, 0.5}, {25, 0.51}};
  b.points.push_back(
      {22.5, 0.5, false, std::nan(""), std::nan(""), QStringLiteral("no admissible Newton step")});
  v.steps = {a, b};
  return v;
}
}  // namespace

void WidgetsTest::hold_chart_draws_measured_T_and_predicted_points() {
  HoldCourseChart chart;
  const auto v = water_course(1);
  chart.show_step(v.steps[0]);
  QCOMPARE(chart.measured_points().size(), std::size_t{51});
  QCOMPARE(chart.measured_points()[50], QPointF(15.0, 0.25));
  QCOMPARE(chart.predicted_points().size(), std::size_t{2});
  QCOMPARE(chart.predicted_points()[1], QPointF(14.5, 0.19));
  const auto bars = chart.error_bars();
  QCOMPARE(bars.size(), std::size_t{2});
  QCOMPARE(bars[0].x, 10.5);
  QCOMPARE(bars[0].lo, 0.18 - 0.004);
  QCOMPARE(bars[0].hi, 0.18 + 0.004);
  QVERIFY(chart.title_text().contains(QStringLiteral("Step 1")));
  // The stopped hold: its measured line, no invented point, the reason in the title.
  chart.show_step(v.steps[1]);
  QCOMPARE(chart.measured_points().size(), std::size_t{2});
  QVERIFY(chart.predicted_points().empty());
  QVERIFY(chart.error_bars().empty());
  QVERIFY(chart.title_text().contains(QStringLiteral("not computed: no admissible Newton step")));
  chart.clear();
  QVERIFY(chart.measured_points().empty());
}

void WidgetsTest::browser_shows_the_hold_of_the_chosen_step() {
  BrowserView view;
  RunDetails d;
  d.listing.id = 7;
  view.show_run(d);
  QVERIFY(view.water_button()->isEnabled());
  QVERIFY(!view.hold_step()->isEnabled());
  view.show_water_course(water_course(8));  // arrived after the user moved to run 7
  QCOMPARE(view.hold_step()->count(), 0);
  view.set_fitting(true);
  QVERIFY2(!view.water_button()->isEnabled(), "one long job at a time");
  view.set_fitting(false);
  view.show_water_course(water_course(7));
  QCOMPARE(view.hold_step()->count(), 2);
  // The deepest computed hold is shown first.
  QCOMPARE(view.hold_step()->currentData().toInt(), 0);
  QCOMPARE(view.hold_chart()->predicted_points().size(), std::size_t{2});
  view.hold_step()->setCurrentIndex(1);
  QVERIFY(view.hold_chart()->predicted_points().empty());
  QVERIFY(view.hold_chart()->title_text().contains(QStringLiteral("Step 2")));
  QVERIFY(view.water_text().contains(QStringLiteral("500 photons")));
  // Reloading the run keeps the course and the chosen step; another run drops it.
  view.show_run(d);
  QCOMPARE(view.hold_step()->currentData().toInt(), 1);
  d.listing.id = 9;
  view.show_run(d);
  QCOMPARE(view.hold_step()->count(), 0);
  QVERIFY(view.hold_chart()->measured_points().empty());
}

namespace {
ScalarGrid grid(int nx, int ny, double scale) {
  ScalarGrid g;
  g.nx = nx;
  g.ny = ny;
  g.x_min = -1;
  g.x_max = 1;
  g.y_min = 0;
  g.y_max = 2;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) g.values.push_back(scale * std::pow(10.0, -iy));
  return g;
}
}  // namespace

void WidgetsTest::colour_map_shares_one_log_scale() {
  FluenceMapPair maps;
  maps.set_dynamic_range_decades(10);
  // Left spans 1e2 .. 1e-1, right 1e0 .. 1e-3: the shared scale is 1e-3 .. 1e2.
  maps.set_maps(grid(3, 4, 100.0), grid(3, 4, 1.0));
  const auto [lo, hi] = maps.log10_range();
  QVERIFY(std::abs(lo - (-3.0)) < 1e-12);
  QVERIFY(std::abs(hi - 2.0) < 1e-12);
  QCOMPARE(maps.colour_of(100.0), FluenceMapPair::ramp(1.0));
  QCOMPARE(maps.colour_of(1e-3), FluenceMapPair::ramp(0.0));
  QCOMPARE(maps.colour_of(1.0), FluenceMapPair::ramp(0.6));  // 3 of 5 decades up
  // Equal values in both panels have equal colours: left (row 2) = 1.0 = right (row 0).
  const QImage& left = maps.panel_image(0);
  const QImage& right = maps.panel_image(1);
  QCOMPARE(left.size(), QSize(3, 4));
  QCOMPARE(left.pixel(1, 4 - 1 - 2), right.pixel(1, 4 - 1 - 0));
  // The dynamic range floor cuts off the noise tail.
  maps.set_dynamic_range_decades(2);
  QVERIFY(std::abs(maps.log10_range().first - 0.0) < 1e-12);
  QCOMPARE(maps.colour_of(1e-3), FluenceMapPair::ramp(0.0));
  // The ramp is dark at the bottom and bright at the top.
  QVERIFY(FluenceMapPair::ramp(0).lightness() < FluenceMapPair::ramp(1).lightness());
}

void WidgetsTest::colour_map_orientation_and_no_data() {
  FluenceMapPair maps;
  ScalarGrid g = grid(2, 3, 1.0);
  g.values[0] = 0.0;  // (0, 0): no photons
  g.values[1] = std::nan("");
  maps.set_maps(g, {});
  const QImage& img = maps.panel_image(0);
  // Row 0 (y_min) is the bottom row of the picture.
  QCOMPARE(QColor(img.pixel(0, 2)), FluenceMapPair::no_data_colour());
  QCOMPARE(QColor(img.pixel(1, 2)), FluenceMapPair::no_data_colour());
  QCOMPARE(QColor(img.pixel(0, 1)), maps.colour_of(0.1));
  QVERIFY(maps.panel_image(1).isNull());
  // Painting with one panel empty must not fail.
  maps.resize(600, 300);
  QVERIFY(!maps.grab().isNull());
  maps.clear();
  QCOMPARE(maps.log10_range().second, 0.0);
}

void WidgetsTest::event_log_is_bounded() {
  EventLog log(nullptr, 10);
  for (int i = 0; i < 25; ++i) {
    log.add(i == 24 ? EventLog::Severity::error : EventLog::Severity::info, QStringLiteral("engine"),
            QStringLiteral("event %1").arg(i));
  }
  QCOMPARE(log.entry_count(), 10);
  QCOMPARE(log.text_of(0), QStringLiteral("event 15"));
  QCOMPARE(log.text_of(9), QStringLiteral("event 24"));
  QVERIFY(log.severity_of(9) == EventLog::Severity::error);
  QCOMPARE(log.count_containing(QStringLiteral("EVENT 2")), 5);  // 20..24
}

void WidgetsTest::instrument_panel_shows_state() {
  InstrumentPanel panel(QStringLiteral("Power meter"));
  QVERIFY(panel.connection() == InstrumentPanel::Connection::absent);
  panel.set_connection(InstrumentPanel::Connection::connected);
  panel.set_identity(QStringLiteral("Thorlabs"), QStringLiteral("PM100D"), QStringLiteral("P001"),
                     QStringLiteral("1.2"));
  QVERIFY(panel.identity_text().contains(QStringLiteral("PM100D")));
  QVERIFY(panel.identity_text().contains(QStringLiteral("P001")));
  panel.set_value(QStringLiteral("power"), 1.25e-3, QStringLiteral("W"));
  panel.set_value(QStringLiteral("power"), 1.5e-3, QStringLiteral("W"));
  QCOMPARE(panel.value_text(), QStringLiteral("power: 0.0015 W"));
  panel.set_value(QStringLiteral("load"), 2.0, QStringLiteral("N"));
  QCOMPARE(panel.value_text(), QStringLiteral("power: 0.0015 W\nload: 2 N"));
  QVERIFY(!panel.fault());
  panel.set_fault(true, QStringLiteral("over range"));
  QVERIFY(panel.fault());
  QCOMPARE(panel.fault_text(), QStringLiteral("over range"));
  panel.set_fault(false);
  QVERIFY(!panel.fault());
}

void WidgetsTest::interlock_indicator_states() {
  InterlockIndicator ind;
  QVERIFY(ind.state() == InterlockIndicator::State::idle);
  ind.set_armed(QStringLiteral("max load 20 N"));
  QVERIFY(ind.state() == InterlockIndicator::State::armed);
  QVERIFY(ind.text().contains(QStringLiteral("20 N")));
  ind.set_tripped(QStringLiteral("load 21.3 N > 20 N"));
  QVERIFY(ind.state() == InterlockIndicator::State::tripped);
  QVERIFY(ind.text().contains(QStringLiteral("21.3")));
}

void WidgetsTest::settings_round_trip() {
  QTemporaryDir dir;
  QVERIFY(dir.isValid());
  const QString file = dir.filePath(QStringLiteral("gui.ini"));
  {
    GuiSettings s(std::make_unique<QSettings>(file, QSettings::IniFormat));
    QCOMPARE(s.photons(), qulonglong{100000});  // first-start defaults
    QVERIFY(s.clock_factor() > 0);
    s.set_last_lab_path(QStringLiteral("/labs/rig.toml"));
    s.set_last_protocol_path(QStringLiteral("/p/steps.toml"));
    s.set_photons(20000);
    s.set_clock_factor(25.0);
    for (int i = 0; i < 12; ++i) s.add_recent_database(QStringLiteral("/db/%1.sqlite").arg(i));
    s.add_recent_database(QStringLiteral("/db/3.sqlite"));
    QMainWindow w;
    w.resize(900, 700);
    s.save_window(w);
    s.sync();
  }
  GuiSettings s(std::make_unique<QSettings>(file, QSettings::IniFormat));
  QCOMPARE(s.last_lab_path(), QStringLiteral("/labs/rig.toml"));
  QCOMPARE(s.last_protocol_path(), QStringLiteral("/p/steps.toml"));
  QCOMPARE(s.photons(), qulonglong{20000});
  QCOMPARE(s.clock_factor(), 25.0);
  const QStringList recent = s.recent_databases();
  QCOMPARE(recent.size(), 8);
  QCOMPARE(recent.front(), QStringLiteral("/db/3.sqlite"));
  QCOMPARE(recent.count(QStringLiteral("/db/3.sqlite")), 1);
  QMainWindow w;
  s.restore_window(w);
  QCOMPARE(w.size(), QSize(900, 700));
  // Garbage in the file falls back to defaults.
  s.raw().setValue("simulation/photons", "lots");
  QCOMPARE(s.photons(), qulonglong{100000});
}

// The panels' titles, and where a run's live reading goes with which unit, come from the
// drivers' capability tables: a channel lands on the panel of the driver that describes it.
void WidgetsTest::lab_view_lays_out_the_drivers_capability_tables() {
  LabView view;
  QCOMPARE(view.panel(InstrumentKind::tester)->title(), QStringLiteral("Mechanical tester"));
  QCOMPARE(view.panel(InstrumentKind::power_meter)->title(), QStringLiteral("Power meter"));
  QCOMPARE(view.panel(InstrumentKind::vacuum)->title(), QStringLiteral("Vacuum controller"));
  view.show_live({{"load", 0.1, 2.0},
                  {"power", 0.1, 1.0e-3},
                  {"displacement", 0.2, 0.5},
                  {"load", 0.2, 3.0},
                  {"pressure", 0.2, 80.0},
                  {"temperature", 0.2, 21.0}});
  QCOMPARE(view.panel(InstrumentKind::tester)->value_text(),
           QStringLiteral("displacement: 0.5 mm\nload: 3 N"));
  QCOMPARE(view.panel(InstrumentKind::power_meter)->value_text(), QStringLiteral("power: 0.001 W"));
  QCOMPARE(view.panel(InstrumentKind::vacuum)->value_text(), QStringLiteral("pressure: 80 kPa"));
  InstrumentReading idle;
  idle.kind = InstrumentKind::vacuum;
  idle.value = 79.5;
  idle.value2 = 80.0;
  view.show_reading(idle);
  QCOMPARE(view.panel(InstrumentKind::vacuum)->value_text(),
           QStringLiteral("pressure: 79.5 kPa\nsetpoint: 80 kPa"));
}

QTEST_MAIN(WidgetsTest)
#include "test_widgets.moc"
