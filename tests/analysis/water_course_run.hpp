#pragma once

// A small hand-made pin-compression run for the water time course tests: displacement at
// 100 Hz, power at 10 Hz, three steps (0, 0.25, 0.5 mm) with their recording windows.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "tester_run.hpp"
#include "tocd/db/database.hpp"
#include "tocd/db/reader.hpp"
#include "tocd/db/writer.hpp"

namespace water_course_test {

constexpr double kBaseline = 2e-3;  // W
constexpr double kThickness = 2.5;  // mm
constexpr std::int64_t kSecond = 1'000'000'000;
constexpr std::int64_t kT0 = 100 * kSecond;  // the run clock does not start at 0

// The pin program: on the surface until 2 s, 0.25 mm at 2.5 s, held to 6 s, 0.5 mm at 6.5 s,
// held to 10 s. The first readings are a little above the surface (approach, negative depth).
inline double depth_at(double t) {
  if (t < 0.3) return -0.01;
  if (t < 2.0) return 0.0;
  if (t < 2.5) return 0.25 * (t - 2.0) / 0.5;
  if (t < 6.0) return 0.25;
  if (t < 6.5) return 0.25 + 0.25 * (t - 6.0) / 0.5;
  return 0.5;
}
// Any power signal will do: the measured side is an average of what was stored.
inline double power_at(int i) {
  return kBaseline * (0.2 + 0.01 * std::sin(0.7 * i) + 0.001 * i);
}

struct Windows {
  double from_s, to_s, depth_mm;
};
inline const std::vector<Windows> kWindows = {{0.5, 1.5, 0.0}, {3.0, 5.0, 0.25}, {7.0, 9.0, 0.5}};

class RunWaterCourse : public tocd::acquisition::testing::TempDatabaseTest {
 protected:
  // A run as the engine records it: displacement at 100 Hz, power at 10 Hz, three steps.
  std::int64_t write_run(bool pin_starts_in_skin = false, bool with_displacement = true) {
    tocd::db::Database db(path_.string());
    tocd::db::SampleRecord sample;
    sample.tissue = "skin";
    sample.thickness_mm = kThickness;
    tocd::db::NewRun nr;
    nr.name = "water course";
    nr.baseline_power_W = kBaseline;
    nr.sample_id = db.add_sample(sample);
    const auto run_id = db.create_run(nr).id;
    tocd::db::Channel dc, pc;
    dc.run_id = pc.run_id = run_id;
    dc.name = "displacement";
    dc.unit = "mm";
    pc.name = "power";
    pc.unit = "W";
    const auto d_id = with_displacement ? db.add_channel(dc).id : 0;
    const auto p_id = db.add_channel(pc).id;
    tocd::db::Writer w(db);
    if (with_displacement)
      for (int i = 0; i <= 1000; ++i) {
        const double t = 0.01 * i;
        const double d = pin_starts_in_skin ? depth_at(t) + 0.1 : depth_at(t);
        w.enqueue(tocd::db::Sample{d_id, kT0 + i * kSecond / 100, d});
        recorded_.push_back({t, d});
      }
    for (int i = 0; i <= 100; ++i) {
      w.enqueue(tocd::db::Sample{p_id, kT0 + i * kSecond / 10, power_at(i)});
      power_.push_back({0.1 * i, power_at(i)});
    }
    for (std::size_t k = 0; k < kWindows.size(); ++k) {
      tocd::db::StepRecord s;
      s.run_id = run_id;
      s.index = static_cast<int>(k);
      s.target_displacement_mm = kWindows[k].depth_mm;
      s.recorded_from_t_ns = kT0 + static_cast<std::int64_t>(kWindows[k].from_s * 1e9);
      s.recorded_to_t_ns = kT0 + static_cast<std::int64_t>(kWindows[k].to_s * 1e9);
      s.completed = true;
      db.add_step(s);
    }
    w.flush();
    w.stop();
    return run_id;
  }

  // Mean of the stored power / baseline over [a, b] s on the run clock, computed here directly.
  double mean_T(double a, double b) const {
    double sum = 0;
    int n = 0;
    for (const auto& [t, P] : power_)
      if (t >= a - 1e-9 && t <= b + 1e-9) {
        sum += P;
        ++n;
      }
    return n ? sum / n / kBaseline : std::nan("");
  }

  std::vector<std::pair<double, double>> recorded_, power_;
};

}  // namespace water_course_test
