// The per-step pipeline: FE (cached) -> composite tet mesh (cached) -> its layout for transport
// (cached) -> its regions for the optics model (cached; the graded levels relabel the layout)
// -> photon Monte Carlo.
#include "tocd/sim/study/predictor.hpp"

#include <cmath>
#include <mutex>
#include <optional>

#include <fmt/format.h>

#include "composite_spec.hpp"
#include "elapsed.hpp"
#include "material_json.hpp"
#include "tocd/core/error.hpp"
#include "tocd/core/log.hpp"
#include "tocd/core/thread_priority.hpp"
#include "tocd/sim/fe/solve.hpp"
#include "tocd/sim/geometry/composite.hpp"
#include "tocd/sim/mc/output.hpp"
#include "tocd/sim/mc/prepared_mesh.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/mc/source.hpp"
#include "tocd/sim/study/fluence_slices.hpp"
#include "tocd/sim/study/keyed_cache.hpp"
#include "tocd/sim/study/profile_adapter.hpp"

namespace tocd::sim::study {
namespace {

/// Throws tocd::Cancelled when the request's cancel flag is set; `where` says what is stopped.
void check_cancel(const PredictionRequest& r, const char* where) {
  if (r.cancel && r.cancel->load()) throw tocd::Cancelled(fmt::format("prediction cancelled {}", where));
}

}  // namespace

// The predictor's cached stages. Named, not anonymous: Predictor::Impl (external linkage)
// holds them.
namespace predictor_cache {

struct FeEntry {
  fe::FeStepResult step;
  double seconds = 0;
};

struct MeshEntry {
  geometry::CompositeMesh composite;
  std::shared_ptr<const FeEntry> fe;  ///< null for the baseline and the flat skin
  double seconds = 0;
};

// A composite mesh laid out for transport with the regions it was built with.
struct LayoutEntry {
  std::shared_ptr<const mc::PreparedMesh> prepared;
  std::shared_ptr<const MeshEntry> mesh;
  std::size_t pin_top_faces = 0;
  double seconds = 0;
};

// The mesh as the request's optics see it: the layout itself, or for the graded optics the
// layout with its skin split into strain levels.
struct PreparedEntry {
  std::shared_ptr<const mc::PreparedMesh> prepared;
  std::shared_ptr<const LayoutEntry> layout;  ///< the mesh and layout it was made from
  std::vector<std::size_t> graded_levels;     ///< tets per graded level (graded model only)
  double seconds = 0;
};

// A run's loading path, solved as far as its last predicted step. The next step of the run
// (its request's fe_path_mm is this path) goes on from here instead of from first touch.
struct LoadingPath {
  std::mutex mutex;
  std::optional<fe::PinCompression> fe;
};

}  // namespace predictor_cache

namespace {

using predictor_cache::FeEntry;
using predictor_cache::LayoutEntry;
using predictor_cache::LoadingPath;
using predictor_cache::MeshEntry;
using predictor_cache::PreparedEntry;

fe::FeModel fe_model(const PredictionRequest& r) {
  fe::FeModel m = fe::FeModel::published_default();
  m.thickness_mm = r.thickness_mm;
  m.outer_radius_mm = r.fe_outer_radius_mm > 0 ? r.fe_outer_radius_mm : 0.5 * r.slide_size_mm;
  m.pin_radius_mm = r.pin_radius_mm;
  m.material = r.material;
  m.mesh_refinement = r.fe_refinement;
  m.kinematics = r.fe_kinematics;
  m.bottom = r.fe_bottom;
  m.compressed_log_strain = r.compressed_log_strain;
  return m;
}

std::string fe_key(const PredictionRequest& r) {
  const nlohmann::json j = {{"d", r.displacement_mm},
                            {"h", r.thickness_mm},
                            {"R", 0.5 * r.slide_size_mm},
                            {"pin", r.pin_radius_mm},
                            {"material", material_to_json(r.material)},
                            {"refine", r.fe_refinement}};
  nlohmann::json k = j;
  if (r.fe_kinematics != fe::Kinematics::axisymmetric) k["kinematics"] = fe::to_string(r.fe_kinematics);
  if (r.fe_bottom != fe::Bottom::bonded) k["bottom"] = fe::to_string(r.fe_bottom);
  if (r.compressed_log_strain != -0.5) k["threshold"] = r.compressed_log_strain;
  if (r.fe_outer_radius_mm > 0) k["R"] = r.fe_outer_radius_mm;
  if (!r.fe_path_mm.empty()) k["path"] = r.fe_path_mm;
  return k.dump();
}

// The FE model of a request whatever its displacement and path: the key of its loading path.
std::string fe_model_key(const PredictionRequest& r) {
  PredictionRequest m = r;
  m.displacement_mm = 0;
  m.fe_path_mm.clear();
  return fe_key(m);
}

// The pin compression of `r` along its fe_path_mm to its displacement: from where `path` is
// when that is the request's path, otherwise solved afresh along it (the same bits either way:
// fe::PinCompression). `path` then ends at the request's displacement.
fe::FeResult solve_along(const PredictionRequest& r, LoadingPath& path,
                         const std::function<void(double)>& on_increment) {
  std::lock_guard lock(path.mutex);
  if (!path.fe || !path.fe->usable() || path.fe->path_mm() != r.fe_path_mm) {
    path.fe.emplace(fe_model(r));
    fe::FeResult earlier = path.fe->advance(r.fe_path_mm, on_increment);
    if (!earlier.complete) return earlier;
  }
  return path.fe->advance({r.displacement_mm}, on_increment);
}

bool needs_fe(const PredictionRequest& r) {
  return !r.baseline && r.displacement_mm > 0.0;
}

std::string mesh_key(const PredictionRequest& r) {
  nlohmann::json j = {{"baseline", r.baseline},        {"preset", r.mesh_preset},
                      {"max_edge", r.max_edge_mm},     {"tip_edge", r.tip_edge_mm},
                      {"pin_length", r.pin_length_mm}, {"pin_radius", r.pin_radius_mm},
                      {"slide", r.slide_size_mm},      {"slide_thickness", r.slide_thickness_mm}};
  if (!r.baseline) {
    j["thickness"] = r.thickness_mm;
    j["displacement"] = r.displacement_mm;
    if (needs_fe(r)) j["fe"] = fe_key(r);
  }
  return j.dump();
}

bool graded(const PredictionRequest& r) {
  return !r.baseline && r.optics_model == "graded";
}

// The graded optics' levels depend on the strain of full clearing and the number of levels,
// not on the cleared optics: a fit that varies mu_a, mu_s and n reuses the split mesh.
std::string prepared_key(const PredictionRequest& r) {
  nlohmann::json j = {{"mesh", mesh_key(r)}, {"model", r.baseline ? "threshold" : r.optics_model}};
  if (graded(r)) j["graded"] = {{"full_strain", r.graded.full_strain}, {"bins", r.graded.bins}};
  return j.dump();
}

nlohmann::json mesh_stats(const PreparedEntry& p) {
  const auto& c = p.layout->mesh->composite;
  nlohmann::json j;
  j["tets"] = c.mesh.tets.size();
  j["nodes"] = c.mesh.nodes.size();
  j["boundary_faces"] = c.mesh.boundary_faces.size();
  j["pin_top_faces"] = p.layout->pin_top_faces;
  j["mesh_seconds"] = c.seconds;
  j["prepare_seconds"] = p.seconds;
  auto& regions = j["regions"] = nlohmann::json::array();
  for (const auto& s : c.regions)
    regions.push_back({{"region", s.region},
                       {"tets", s.tets},
                       {"volume_mm3", s.volume_mm3},
                       {"expected_volume_mm3", s.expected_volume_mm3}});
  if (!p.graded_levels.empty()) j["graded_levels_tets"] = p.graded_levels;
  return j;
}

}  // namespace

tocd::sim::material::OgdenParameters published_skin_material() {
  return fe::FeModel::published_default().material;
}

struct Predictor::Impl {
  KeyedCache<FeEntry> fe{32};
  KeyedCache<MeshEntry> meshes{8};
  KeyedCache<LayoutEntry> layouts{8};
  KeyedCache<PreparedEntry> prepared{8};

  // A few loading paths at once (a recording has one; the window may hold runs of several);
  // past that the one used least recently goes. The cache holds a pointer to each: a path is
  // advanced in place, under its own lock.
  KeyedCache<std::shared_ptr<LoadingPath>> paths{4};

  std::shared_ptr<LoadingPath> loading_path(const PredictionRequest& r) {
    return *paths.get_or_compute(fe_model_key(r), [] { return std::make_shared<LoadingPath>(); }).value;
  }

  std::shared_ptr<const FeEntry> solve_fe(const PredictionRequest& r, bool& hit) {
    auto got = fe.get_or_compute(fe_key(r), [&] {
      const auto t0 = Clock::now();
      const auto on_increment = [&r](double) { check_cancel(r, "during the FE solve"); };
      fe::FeResult res = r.fe_path_mm.empty() ? fe::solve(fe_model(r), {r.displacement_mm}, on_increment)
                                              : solve_along(r, *loading_path(r), on_increment);
      if (!res.complete || res.steps.empty())
        throw tocd::Error(fmt::format("FE solve to {} mm in {} mm skin stopped: {}", r.displacement_mm,
                                      r.thickness_mm, res.stop_reason));
      FeEntry e{res.steps.back(), 0.0};
      e.seconds = seconds_since(t0);
      return e;
    });
    hit = got.hit;
    return got.value;
  }

  std::shared_ptr<const MeshEntry> build_mesh(const PredictionRequest& r, bool& fe_hit, bool& mesh_hit) {
    std::shared_ptr<const FeEntry> fe_entry;
    fe_hit = true;
    if (needs_fe(r)) fe_entry = solve_fe(r, fe_hit);
    auto got = meshes.get_or_compute(mesh_key(r), [&] {
      check_cancel(r, "before meshing");
      const auto t0 = Clock::now();
      const geometry::SkinProfile profile =
          fe_entry ? to_skin_profile(fe_entry->step, r.thickness_mm) : flat_skin_profile(r.thickness_mm);
      MeshEntry m{geometry::build_composite(composite_spec(r, profile), r.cancel.get()), fe_entry, 0.0};
      m.seconds = seconds_since(t0);
      return m;
    });
    mesh_hit = got.hit;
    return got.value;
  }

  // Validating and laying out a mesh for transport costs as much as the Monte Carlo of a
  // small run: done once per mesh, whatever the optics.
  std::shared_ptr<const LayoutEntry> lay_out(const PredictionRequest& r, bool& fe_hit, bool& mesh_hit,
                                             bool& layout_hit) {
    auto got = layouts.get_or_compute(mesh_key(r), [&] {
      LayoutEntry e;
      e.mesh = build_mesh(r, fe_hit, mesh_hit);
      const auto t0 = Clock::now();
      for (const auto& f : e.mesh->composite.mesh.boundary_faces)
        e.pin_top_faces += f.marker == geometry::Marker::pin_top ? 1 : 0;
      if (e.pin_top_faces == 0)
        throw tocd::Error("composite mesh: no boundary face carries the pin-top marker (the light source)");
      e.prepared = std::make_shared<const mc::PreparedMesh>(mc::prepare(e.mesh->composite.mesh));
      e.seconds = seconds_since(t0);
      return e;
    });
    layout_hit = got.hit;
    return got.value;
  }

  std::shared_ptr<const PreparedEntry> prepare(const PredictionRequest& r, bool& fe_hit, bool& mesh_hit) {
    bool inner_mesh_hit = true;
    auto got = prepared.get_or_compute(prepared_key(r), [&] {
      bool layout_hit = true;
      const auto layout = lay_out(r, fe_hit, inner_mesh_hit, layout_hit);
      const auto t0 = Clock::now();
      PreparedEntry p{layout->prepared, layout, {}, 0.0};
      if (graded(r)) {
        mesh::TetMesh split = layout->prepared->mesh;
        const FeEntry* f = layout->mesh->fe.get();
        p.graded_levels = assign_graded_regions(
            split, r.graded, [f](double rr, double z) { return f ? f->step.min_log_strain_at(rr, z) : 0.0; });
        p.prepared = std::make_shared<const mc::PreparedMesh>(
            mc::relabel(*layout->prepared, std::move(split.regions)));
      }
      p.seconds = (layout_hit ? 0.0 : layout->seconds) + seconds_since(t0);
      return p;
    });
    mesh_hit = inner_mesh_hit;
    return got.value;
  }
};

// A request with its FE, mesh and Monte Carlo inputs ready: everything of a prediction but
// the photons.
struct Predictor::Staged {
  Prediction out;
  std::shared_ptr<const PreparedEntry> prepared;
  mc::Optics optics;
  mc::Source source;
  mc::RunSettings settings;
};

Predictor::Staged Predictor::stage(const PredictionRequest& r) {
  Staged st;
  Prediction& out = st.out;
  out.config = to_config(r);  // validates
  check_cancel(r, "before the FE solve");
  const auto t_fe = Clock::now();
  bool fe_hit = true, mesh_hit = true;
  // FE first (its time is reported apart), then mesh and preparation.
  std::shared_ptr<const FeEntry> fe_entry;
  if (needs_fe(r)) fe_entry = impl_->solve_fe(r, fe_hit);
  out.fe_seconds = seconds_since(t_fe);
  const auto t_mesh = Clock::now();
  bool ignored = true;
  st.prepared = impl_->prepare(r, ignored, mesh_hit);
  out.mesh_seconds = seconds_since(t_mesh);
  out.fe_cached = fe_hit;
  out.mesh_cached = mesh_hit;

  if (r.baseline)
    out.fe_summary = {{"baseline", true}};
  else if (!fe_entry)
    out.fe_summary = {{"displacement_mm", 0.0}, {"flat", true}};
  else {
    out.fe_summary = summarise(fe_entry->step);
    out.fe_summary["solve_seconds"] = fe_entry->seconds;
  }
  out.fe_summary["cached"] = fe_hit;
  out.mesh_stats = mesh_stats(*st.prepared);
  out.mesh_stats["cached"] = mesh_hit;
  out.tets = st.prepared->prepared->mesh.tets.size();

  st.optics = optics_of(r);
  st.source.kind = mc::Source::Kind::marker;
  st.source.marker = geometry::Marker::pin_top;
  mc::RunSettings& s = st.settings;
  s.photons = r.photons;
  s.seed = r.seed;
  s.batches = r.batches;
  s.threads = r.threads > 0 ? r.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  s.ambient_n = 1.0;
  s.tally_per_tet = !r.fluence_dir.empty();
  s.transmittance_derivatives = r.transmittance_derivatives;
  s.progress = r.mc_progress;
  s.cancel = r.cancel.get();
  check_cancel(r, "after meshing");
  return st;
}

void Predictor::complete(const PredictionRequest& r, Staged& st, const mc::Result& res) {
  Prediction& out = st.out;
  out.mc_seconds = res.seconds;
  out.T = res.transmittance.mean;
  out.T_stderr = res.transmittance.se;
  out.side_loss = res.side_loss.mean;
  out.side_loss_stderr = res.side_loss.se;
  if (const auto it = res.exit_by_marker.find(geometry::Marker::slide_sides);
      it != res.exit_by_marker.end()) {
    out.side_loss_slide = it->second.mean;
    out.side_loss_slide_stderr = it->second.se;
  }
  out.reflectance = res.reflectance.mean;
  out.absorbed = res.absorbed.mean;
  out.specular = res.specular.mean;
  out.dT_dmu = res.transmittance_derivatives;  // empty unless requested
  out.mc = mc::to_json(res);
  out.mc["source"] = mc::describe(st.source);
  out.config["optics"] = optics_record(r);

  if (!r.fluence_dir.empty()) {
    const double tip_z = r.baseline ? 0.0 : r.thickness_mm - r.displacement_mm;
    const std::string stem = r.fluence_stem.empty() ? "prediction" : r.fluence_stem;
    const auto files = fluence_file_names(r.fluence_dir, stem);
    // Every member of a team has the same result; one writes it.
    if (!team_ || team_->rank() == 0)
      write_fluence_files(*st.prepared->prepared, res, tip_z, r.fluence_dir, stem, 0.05, r.vtu_format);
    out.fluence = {{"vtu", files.vtu.string()},
                   {"horizontal_csv", files.horizontal_csv.string()},
                   {"vertical_csv", files.vertical_csv.string()},
                   {"horizontal_z_mm", tip_z}};
  }
}

Prediction Predictor::predict(const PredictionRequest& r) {
  Staged st = stage(r);
  st.settings.team = team_;
  const mc::Result res = mc::run(*st.prepared->prepared, st.optics, st.source, st.settings);
  if (res.cancelled) {
    throw tocd::Cancelled(fmt::format("prediction cancelled during the Monte Carlo ({} of {} photons)",
                                      res.photons, r.photons));
  }
  complete(r, st, res);
  return std::move(st.out);
}

mc::Tallies Predictor::run_batches(const PredictionRequest& r, int first_batch, int last_batch) {
  const Staged st = stage(r);
  return mc::run_batches(*st.prepared->prepared, st.optics, st.source, st.settings, first_batch, last_batch);
}

Prediction Predictor::assemble(const PredictionRequest& r, const mc::Tallies& summed, double mc_seconds) {
  Staged st = stage(r);
  mc::Result res = mc::finish(*st.prepared->prepared, st.optics, st.settings, summed);
  res.seconds = mc_seconds;
  res.photons_per_second = mc_seconds > 0 ? static_cast<double>(res.photons) / mc_seconds : 0.0;
  res.events_per_second = mc_seconds > 0 ? static_cast<double>(res.events) / mc_seconds : 0.0;
  complete(r, st, res);
  return std::move(st.out);
}

Predictor::Predictor(int worker_threads, parallel::Team* team, bool background)
    : impl_(std::make_unique<Impl>()), team_(team && team->size() > 1 ? team : nullptr) {
  const int n = std::max(1, worker_threads);
  for (int i = 0; i < n; ++i) workers_.emplace_back([this, background] { work(background); });
}

Predictor::~Predictor() {
  {
    std::lock_guard lock(queue_mutex_);
    stopping_ = true;
  }
  queue_cv_.notify_all();
  for (auto& w : workers_) w.join();
}

std::future<Prediction> Predictor::submit(const PredictionRequest& r) {
  std::packaged_task<Prediction()> task([this, r] { return predict(r); });
  auto future = task.get_future();
  {
    std::lock_guard lock(queue_mutex_);
    if (stopping_) throw tocd::Error("predictor is shutting down");
    queue_.push_back(std::move(task));
  }
  queue_cv_.notify_one();
  return future;
}

void Predictor::work(bool background) {
  // Before the first Monte Carlo: the OpenMP threads this thread starts inherit its priority.
  if (background && !run_this_thread_in_background())
    tocd::logger("sim")->warn("prediction worker: could not lower its scheduling priority");
  for (;;) {
    std::packaged_task<Prediction()> task;
    {
      std::unique_lock lock(queue_mutex_);
      queue_cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    task();  // exceptions go into the future
  }
}

Predictor::CacheCounts Predictor::cache_counts() const {
  return {impl_->fe.hits(), impl_->fe.misses(), impl_->meshes.hits(), impl_->meshes.misses()};
}

nlohmann::json to_json(const Prediction& p) {
  nlohmann::json j = {{"T", p.T},
                      {"T_se", p.T_stderr},
                      {"side_loss", p.side_loss},
                      {"side_loss_se", p.side_loss_stderr},
                      {"side_loss_slide", p.side_loss_slide},
                      {"side_loss_slide_se", p.side_loss_slide_stderr},
                      {"reflectance", p.reflectance},
                      {"absorbed", p.absorbed},
                      {"specular", p.specular},
                      {"tets", p.tets},
                      {"fe_seconds", p.fe_seconds},
                      {"mesh_seconds", p.mesh_seconds},
                      {"mc_seconds", p.mc_seconds},
                      {"config", p.config},
                      {"fe_summary", p.fe_summary},
                      {"mesh_stats", p.mesh_stats},
                      {"mc", p.mc}};
  if (!p.fluence.is_null()) j["fluence"] = p.fluence;
  return j;
}

}  // namespace tocd::sim::study
