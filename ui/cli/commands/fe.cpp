// `tocdlab fe`: finite-strain FE of a rigid pin pressed into a skin slab (docs/fe.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "progress.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "vtu_format_option.hpp"

namespace cli = tocd::cli;

namespace {

struct FeOptions {
  std::string displacements = "0.625,1.25,1.5", bottom = "bonded", kinematics = "axi", vtu;
  double thickness_mm = 2.5, outer_radius_mm = 6.25, pin_radius_mm = 1.5, refinement = 1.0, depth_mm = 1.0;
  bool json = false;
  tocd::sim::vtk::Format vtu_format = tocd::sim::vtk::Format::binary;
};

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) {
    std::size_t used = 0;
    double x = 0;
    try {
      x = std::stod(item, &used);
    } catch (...) {
      used = 0;
    }
    if (used == 0 || used != item.size())
      throw tocd::sim::fe::FeError(
          fmt::format("--displacement: '{}' is not a number (give mm, comma separated)", item));
    if (!(x > 0.0 && x <= 100.0))
      throw tocd::sim::fe::FeError(
          fmt::format("--displacement: {} is out of range: accepted above 0 up to 100 mm", item));
    v.push_back(x);
  }
  return v;
}

std::filesystem::path step_path(const std::string& base, std::size_t index, std::size_t count) {
  if (count == 1) return base;
  std::filesystem::path p(base);
  return p.parent_path() / fmt::format("{}_{}{}", p.stem().string(), index + 1, p.extension().string());
}

void run_fe(const FeOptions& o) {
  namespace fe = tocd::sim::fe;
  fe::FeModel m = fe::FeModel::published_default();
  m.thickness_mm = o.thickness_mm;
  m.outer_radius_mm = o.outer_radius_mm;
  m.pin_radius_mm = o.pin_radius_mm;
  m.mesh_refinement = o.refinement;
  m.depth_mm = o.depth_mm;
  m.bottom = fe::parse_bottom(o.bottom);
  m.kinematics = fe::parse_kinematics(o.kinematics);
  const std::vector<double> displacements = parse_list(o.displacements);
  // Progress counts pin travel in micrometres: the rate and ETA follow the load increments.
  const fe::FeResult r = [&] {
    const double target_mm = displacements.empty() ? 0.0 : displacements.back();
    cli::ProgressBar bar(fmt::format("fe: {} step(s) to {} mm", displacements.size(), target_mm),
                         static_cast<std::uint64_t>(std::llround(target_mm * 1000)), "um");
    fe::FeResult solved = fe::solve(m, displacements, [&bar](double d_mm) {
      bar.update(static_cast<std::uint64_t>(std::llround(d_mm * 1000)));
    });
    bar.finish();
    return solved;
  }();
  if (!o.vtu.empty())
    for (std::size_t k = 0; k < r.steps.size(); ++k) {
      const auto path = step_path(o.vtu, k, r.steps.size());
      fe::write_vtu(r.steps[k], path, o.vtu_format);
      cli::announce_file(fmt::format("step {} mesh", k + 1), path.string());
    }
  if (o.json) {
    cli::print_json(fe::to_json(r));
    return;
  }
  std::cout << fmt::format("{} skin {} mm, pin radius {} mm, bottom {}\n", fe::to_string(m.kinematics),
                           m.thickness_mm, m.pin_radius_mm, fe::to_string(m.bottom));
  std::cout << fmt::format("{:>4} {:>8} {:>8} {:>10} {:>12} {:>12} {:>9} {:>7} {:>6}\n", "step", "d [mm]",
                           "strain", "force [N]", "area [mm2]", "vol [mm3]", "min LE", "incr", "Newton");
  for (std::size_t k = 0; k < r.steps.size(); ++k) {
    const auto& s = r.steps[k];
    double le = 0;
    for (double v : s.element_min_log_strain) le = std::min(le, v);
    std::cout << fmt::format("{:4d} {:8.4f} {:8.3f} {:10.5f} {:12.4f} {:12.4f} {:9.3f} {:7d} {:6d}\n", k + 1,
                             s.displacement_mm, s.displacement_mm / m.thickness_mm, s.force_N,
                             s.compressed_area_mm2, s.compressed_volume_mm3, le, s.load_increments,
                             s.newton_iterations);
  }
  std::cout << fmt::format("{} increments, {} Newton iterations, {:.2f} s{}\n", r.total_load_increments,
                           r.total_newton_iterations, r.seconds,
                           r.complete ? "" : "  INCOMPLETE: " + r.stop_reason);
}

void install_fe(CLI::App& root) {
  auto* cmd = root.add_subcommand("fe", "Finite-strain FE of a rigid pin pressed into skin (see docs/fe.md)");
  auto o = std::make_shared<FeOptions>();
  cmd->add_option("--displacement", o->displacements, "pin displacements [mm], ascending, comma separated")
      ->check(CLI::Validator(
          [](std::string& text) {
            // A bad list is a usage error (exit 2) like every other refused option value.
            try {
              (void)parse_list(text);
              return std::string();
            } catch (const tocd::sim::fe::FeError& e) {
              const std::string what = e.what(), prefix = "--displacement: ";
              return what.starts_with(prefix) ? what.substr(prefix.size()) : what;
            }
          },
          "MM[,MM...]"))
      ->capture_default_str();
  cmd->add_option("--bottom", o->bottom, "skin on the slide: bonded | sliding")->capture_default_str();
  cmd->add_option("--kinematics", o->kinematics, "axi | plane-strain | plane-stress")->capture_default_str();
  cli::add_ranged_option(cmd, "--thickness", o->thickness_mm, "skin thickness [mm]",
                         cli::real_above(0.0, 100.0));
  cli::add_ranged_option(cmd, "--radius", o->outer_radius_mm, "skin radius (half width) [mm]",
                         cli::real_above(0.0, 1000.0));
  cli::add_ranged_option(cmd, "--pin-radius", o->pin_radius_mm, "pin tip radius [mm]",
                         cli::real_above(0.0, 100.0));
  cli::add_ranged_option(cmd, "--refine", o->refinement, "mesh refinement factor (2 = twice as fine)",
                         cli::real_above(0.0, 16.0));
  cli::add_ranged_option(cmd, "--depth", o->depth_mm, "plane kinematics: out-of-plane depth [mm]",
                         cli::real_above(0.0, 1000.0));
  cmd->add_flag("--json", o->json, "machine-readable output");
  cli::add_vtu_output_options(cmd, o->vtu, o->vtu_format,
                              "write the deformed mesh (.vtu, one file per step: NAME_k.vtu)");
  cmd->callback([o] { run_fe(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(fe, install_fe);
