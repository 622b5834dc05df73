// The run browser's water time course: analysis::run_water_course on the long-job worker,
// turned into what the hold chart draws.
#include <cmath>

#include "backend_db.hpp"
#include "background.hpp"
#include "tocd/analysis/run_water_course.hpp"

namespace tocd::gui {

namespace {

// Every stored power sample of the step's window as T, for the measured line of the hold.
std::vector<QPointF> measured_over(const db::Reader& reader, std::int64_t run_id, const db::StepRecord& step,
                                   std::int64_t t0_ns) {
  std::vector<QPointF> out;
  const auto power = reader.channel(run_id, "power");
  const double P0 = reader.run(run_id).baseline_power_W;
  if (!power || !(P0 > 0)) return out;
  db::SampleQuery q;
  q.from_t_ns = step.recorded_from_t_ns;
  q.to_t_ns = step.recorded_to_t_ns;
  for (const auto& s : reader.samples(power->id, q))
    if (std::isfinite(s.value)) out.emplace_back(static_cast<double>(s.t_ns - t0_ns) * 1e-9, s.value / P0);
  return out;
}

// The hold chart's view of one step of the course: its window, the measured line and the points.
WaterStepView water_step_view(const analysis::WaterCourseStep& s, std::vector<QPointF> measured) {
  std::vector<WaterPointView> points;
  for (const auto& p : s.points)
    points.push_back({p.t_s, p.measured.T, p.predicted.computed, p.T, p.T_se,
                      QString::fromStdString(p.predicted.failure)});
  return {.step = s.index,
          .displacement_mm = s.target_displacement_mm,
          .window_from_s = s.window_from_s,
          .window_to_s = s.window_to_s,
          .measured = std::move(measured),
          .points = std::move(points)};
}

}  // namespace

void RunBrowserBackend::water_course(std::int64_t run_id, std::uint64_t photons) {
  if (!reader_ || fitting()) return;
  const std::string path = path_.toStdString();  // a reader of its own, as the fit
  fits_->run<WaterCourseView>(
      [this, path, run_id, photons] {
        analysis::RunWaterCourseOptions o;
        o.photons = photons;
        o.progress = [this](const std::string& line) {
          QMetaObject::invokeMethod(
              this, [this, l = QString::fromStdString(line)] { emit water_progress(l); },
              Qt::QueuedConnection);
        };
        o.point_progress = [this](std::size_t done, std::size_t all) {
          QMetaObject::invokeMethod(
              this,
              [this, done, all] {
                emit water_progress(tr("water time course: %1 of %2 points").arg(done).arg(all));
              },
              Qt::QueuedConnection);
        };
        const db::Reader reader(path);
        const auto c = analysis::run_water_course(reader, run_id, o);
        const auto steps = reader.steps(run_id);
        WaterCourseView v;
        v.run_id = run_id;
        v.summary = tr("water optics along the recorded displacement, %1 photons per point, %2 s")
                        .arg(photons)
                        .arg(c.seconds, 0, 'f', 1);
        for (const auto& s : c.steps) {
          std::vector<QPointF> measured;
          for (const auto& rec : steps)
            if (rec.index == s.index) measured = measured_over(reader, run_id, rec, c.history.t0_ns);
          v.steps.push_back(water_step_view(s, std::move(measured)));
        }
        return v;
      },
      [this](WaterCourseView& v) { emit water_course_ready(v); },
      [this, run_id](const QString& message) {
        emit failed(tr("Water time course of run %1").arg(run_id), message);
      });
}

}  // namespace tocd::gui
