// `tocdlab mc`: photon Monte Carlo on a TetGen mesh or a built-in slab (docs/mc.md).
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "command_registry.hpp"
#include "numeric_options.hpp"
#include "output_naming.hpp"
#include "output_paths.hpp"
#include "progress.hpp"
#include "tocd/core/error.hpp"
#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mc/output.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mc/source.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/mesh/tetgen_io.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "vtu_format_option.hpp"

namespace cli = tocd::cli;

namespace {

struct McOptions {
  std::string mesh_prefix, slab, optics_file, source = "pencil", vtu;
  int slab_cells = 20;
  std::uint64_t photons = 100000, seed = 1;
  int threads = 0, batches = 20;
  std::optional<double> ambient_n;
  bool json = false;
  tocd::sim::vtk::Format vtu_format = tocd::sim::vtk::Format::binary;
};

void print_text(const tocd::sim::mc::Result& r, const std::string& source) {
  auto line = [](const char* name, const tocd::sim::mc::Estimate& e) {
    std::cout << fmt::format("  {:<18} {:.6f} +- {:.6f}\n", name, e.mean, e.se);
  };
  std::cout << fmt::format("{} photons, seed {}, {} threads{}, {} batches; source: {}\n", r.photons, r.seed,
                           r.threads, r.ranks > 1 ? fmt::format(" x {} ranks", r.ranks) : "", r.batches,
                           source);
  line("transmittance", r.transmittance);
  line("reflectance", r.reflectance);
  line("side loss", r.side_loss);
  line("absorbed", r.absorbed);
  line("specular", r.specular);
  if (r.missed.mean > 0.0) line("missed", r.missed);
  for (const auto& [m, e] : r.exit_by_marker) line(fmt::format("exit marker {}", m).c_str(), e);
  std::cout << fmt::format("  {:.2f} s, {:.0f} photons/s, {:.3g} events/s, energy balance error {:.1e}{}\n",
                           r.seconds, r.photons_per_second, r.events_per_second, r.energy_balance_error,
                           r.cancelled ? " (cancelled)" : "");
}

void run_mc(const McOptions& o) {
  namespace mc = tocd::sim::mc;
  namespace msh = tocd::sim::mesh;
  if (o.mesh_prefix.empty() == o.slab.empty())
    throw tocd::ConfigError("give exactly one of --mesh PREFIX or --slab SPEC");
  const mc::PreparedMesh mesh =
      mc::prepare(o.slab.empty() ? msh::read_tetgen(o.mesh_prefix)
                                 : msh::make_slab(msh::parse_slab_spec(o.slab, o.slab_cells)));
  const mc::Optics optics = mc::load_optics_toml(o.optics_file);
  const mc::Source source = mc::parse_source(o.source, mesh.box);
  mc::RunSettings s;
  s.photons = o.photons;
  s.seed = o.seed;
  s.threads = cli::resolve_threads(o.threads);
  s.batches = o.batches;
  s.ambient_n = o.ambient_n ? *o.ambient_n : (optics.ambient_n > 0.0 ? optics.ambient_n : 1.0);
  s.tally_per_tet = !o.vtu.empty();
  s.team = &tocd::sim::parallel::world();  // under mpirun the ranks share the photons
  std::optional<cli::ProgressBar> bar;
  if (s.team->rank() == 0) bar.emplace("mc", o.photons, "photons");
  s.progress = [&bar](std::uint64_t done, std::uint64_t) {
    if (bar) bar->update(done);
  };
  const mc::Result r = mc::run(mesh, optics, source, s);
  if (bar) {
    bar->update(r.photons);
    bar->finish();
  }
  if (!o.vtu.empty() && s.team->rank() == 0) {
    mc::write_fluence_vtu(mesh, r, o.vtu, o.vtu_format);
    cli::announce_file("fluence", o.vtu);
  }
  if (o.json) {
    nlohmann::json j = mc::to_json(r);
    j["source"] = mc::describe(source);
    j["tets"] = mesh.tets.size();
    j["ambient_n"] = s.ambient_n;
    if (!o.vtu.empty()) j["vtu"] = o.vtu;
    cli::print_json(j);
  } else {
    print_text(r, mc::describe(source));
  }
}

void install_mc(CLI::App& root) {
  auto* cmd = root.add_subcommand("mc", "Photon Monte Carlo through a tetrahedral mesh (see docs/mc.md)");
  auto o = std::make_shared<McOptions>();
  cmd->add_option("--mesh", o->mesh_prefix, "TetGen mesh prefix (PREFIX.node, .ele, optional .face)");
  cmd->add_option("--slab", o->slab, "built-in slab: WxDxT or WxD:T1@R1,T2@R2,... (mm, layers top-down)");
  cli::add_ranged_option(cmd, "--slab-cells", o->slab_cells, "slab cells across x and y",
                         cli::whole_in(std::int64_t{1}, std::int64_t{1000}));
  cmd->add_option("--optics", o->optics_file, "optics TOML: [region.<id>] mu_a, mu_s (1/mm), g, n")
      ->required();
  cmd->add_option("--source", o->source,
                  "pencil[:X,Y] | disk:[X,Y,]R | marker:N  (',nospec' = no entry specular)")
      ->capture_default_str();
  cli::add_photons_option(*cmd, "--photons", o->photons, "photons to launch");
  cli::add_seed_option(*cmd, o->seed, "random seed");
  cli::add_threads_option(*cmd, o->threads, "threads (0 = all cores; results do not depend on it)");
  cli::add_ranged_option(cmd, "--batches", o->batches, "batches for standard errors",
                         cli::whole_in(std::int64_t{2}, std::int64_t{1000000}));
  cmd->add_option("--ambient-n", o->ambient_n,
                  "refractive index outside the mesh (default: optics file, else 1.0)")
      ->check(cli::real_in(1.0, 5.0));
  cmd->add_flag("--json", o->json, "machine-readable output");
  cli::add_vtu_output_options(cmd, o->vtu, o->vtu_format,
                              "write per-tet fluence to this .vtu file (ParaView)");
  cmd->callback([o] { run_mc(*o); });
}

}  // namespace

TOCD_CLI_COMMAND(mc, install_mc);
