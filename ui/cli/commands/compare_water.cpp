// The water branch of `tocdlab compare`: the numbers come from analysis::run_water_course,
// this file lays them out; progress on stderr.
#include "compare_water.hpp"

#include <iostream>

#include "output_naming.hpp"
#include "progress.hpp"
#include "tocd/db/reader.hpp"

namespace tocd::cli {

void run_compare_water(CompareWaterOptions o) {
  const db::Reader reader(o.db);
  // Total unknown until the time points are laid out (the first progress call).
  ProgressBar bar("compare: water time course (FE along the run, mesh + Monte Carlo per point)", 0,
                  "time points");
  o.course.progress = [&bar](const std::string& line) { bar.note(line); };
  o.course.point_progress = [&bar](std::size_t done, std::size_t all) {
    bar.set_total(all);
    bar.update(done);
  };
  const auto c = analysis::run_water_course(reader, o.run, o.course);
  bar.finish();
  if (o.json)
    print_json(analysis::to_json(c));
  else
    std::cout << analysis::format_run_water_course(c);
  if (!progress_quiet()) std::cerr << "compare --optics water: " << c.seconds << " s wall\n";
}

}  // namespace tocd::cli
