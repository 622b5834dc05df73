#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "tocd/sim/fe/model.hpp"
#include "tocd/sim/material/ogden.hpp"
#include "tocd/sim/mc/optics.hpp"
#include "tocd/sim/mc/run.hpp"
#include "tocd/sim/parallel/team.hpp"
#include "tocd/sim/study/study_optics.hpp"
#include "tocd/sim/vtk/vtu.hpp"

namespace tocd::sim::study {

/// The published skin material (FeModel::published_default().material).
tocd::sim::material::OgdenParameters published_skin_material();

/// One compression step to simulate: FE (pin pushed `displacement_mm` into a skin slab of
/// `thickness_mm`), composite tet mesh, photon Monte Carlo. See docs/study.md.
struct PredictionRequest {
  double displacement_mm = 0;
  double thickness_mm = 2.5;
  tocd::sim::material::OgdenParameters material = published_skin_material();
  std::string optics_model = "threshold";  ///< "threshold" | "graded"
  std::uint64_t photons = 100000;
  std::uint64_t seed = 1;
  std::string mesh_preset = "fast";  ///< "fast" | "paper"
  int threads = 0;                   ///< Monte Carlo threads, 0 = all cores; results do not depend on it

  // Beyond the contract (all part of the reproducing config):
  bool baseline = false;  ///< glass only: pin tip on the slide, no skin (simulation 0)
  /// Optics of the compressed region (threshold model): every skin element with minimum
  /// principal log strain <= -0.5. Default: the most cleared state of the study.
  mc::RegionOptics compressed_optics = cleared_skin_optics();
  GradedOptics graded;     ///< used when optics_model == "graded"
  int batches = 20;        ///< Monte Carlo batches for standard errors
  double max_edge_mm = 0;  ///< > 0 overrides the preset's element size
  double tip_edge_mm = 0;  ///< > 0 overrides the pin tip's segment length
  double pin_length_mm = 3.3, pin_radius_mm = 1.5;
  double slide_size_mm = 12.5, slide_thickness_mm = 1.0;
  double fe_refinement = 1.0;  ///< FeModel::mesh_refinement
  /// FE modelling choices (the sensitivity study varies them). Written to the config only
  /// when they differ from these defaults, so earlier configs read back unchanged.
  fe::Kinematics fe_kinematics = fe::Kinematics::axisymmetric;
  fe::Bottom fe_bottom = fe::Bottom::bonded;
  double compressed_log_strain = -0.5;  ///< threshold of the compressed region (FeModel)
  double fe_outer_radius_mm = 0;        ///< FE sample half width; 0 = half the slide size
  /// The loading path this step's FE continues: the displacements (ascending, each above 0 and
  /// below displacement_mm) the pin went through before it, as a run's earlier steps. The FE
  /// solves through them to displacement_mm (fe::PinCompression); a predictor that solved the
  /// path already goes on from its end. Empty: solved from first touch. In the config when not
  /// empty, so a stored prediction is reproduced along the same path, to the bit.
  std::vector<double> fe_path_mm;
  double slide_n = 0;  ///< refractive index of the slide; 0 = the glass of the model note
  /// When not empty: per-tet fluence .vtu and two slice CSVs go to this folder, named
  /// `fluence_stem` (default "prediction"). Not part of the config.
  std::string fluence_dir, fluence_stem;
  vtk::Format vtu_format = vtk::Format::binary;  ///< of the fluence .vtu; not part of the config
  /// Called now and then during the Monte Carlo with (photons done, photons asked), as
  /// mc::RunSettings::progress; FE and meshing come before its first call. Not part of the config.
  std::function<void(std::uint64_t, std::uint64_t)> mc_progress;
  /// When set, the prediction checks it between FE increments, before and after meshing and
  /// between Monte Carlo photons, and once it reads true throws tocd::Cancelled (a mesh that
  /// TetGen has begun is finished first). Not part of the config.
  std::shared_ptr<const std::atomic<bool>> cancel;
  /// Also estimate dT/dmu_a and dT/dmu_s of every region by perturbation Monte Carlo
  /// (Prediction::dT_dmu; mc::RunSettings::transmittance_derivatives). Not part of the config:
  /// it adds estimates but never changes T or any other answer (the photon histories are the
  /// same bit for bit), so predictions with and without it share their config and caches.
  bool transmittance_derivatives = false;
};

struct Prediction {
  double T = 0, T_stderr = 0, side_loss = 0;
  double fe_seconds = 0, mesh_seconds = 0, mc_seconds = 0;
  nlohmann::json config;  ///< everything needed to reproduce it (request_from_config reads it back)
  nlohmann::json fe_summary, mesh_stats;

  double side_loss_stderr = 0, reflectance = 0, absorbed = 0, specular = 0;
  /// The part of side_loss that leaves through the slide's edges: light the slide guides
  /// sideways by total internal reflection, as opposed to light diffusing out of the skin.
  double side_loss_slide = 0, side_loss_slide_stderr = 0;
  std::size_t tets = 0;
  bool fe_cached = false, mesh_cached = false;  ///< taken from the predictor's caches
  nlohmann::json mc;                            ///< the Monte Carlo summary (mc::to_json)
  nlohmann::json fluence;                       ///< paths of the fluence files, when written
  /// When the request asked for them: per region id of the step's mesh (the threshold
  /// model's 1-5, or the graded levels kGradedRegionBase + k), dT/dmu_a and dT/dmu_s in mm of
  /// the T above, the step's own (raw Monte Carlo) transmittance. For a T relative to the
  /// glass-only baseline (T / T_baseline, as a run stores it) divide them by T_baseline: the
  /// baseline holds no skin, so T_baseline does not depend on the skin's optics (it does on
  /// the glass and air regions the two meshes share).
  std::map<std::int32_t, mc::TransmittanceDerivative> dT_dmu;
};

/// A prediction as `tocdlab predict --json` and the study tables write it: T, side losses,
/// reflectance, absorption, the timings, config, FE summary, mesh statistics, the Monte Carlo
/// summary and, when written, the fluence files (the derivatives are left out).
nlohmann::json to_json(const Prediction& p);

/// Canonical config of a request (threads and fluence output excluded: they do not change
/// the answer). Throws tocd::ConfigError on a bad request (names the field).
nlohmann::json to_config(const PredictionRequest& request);
/// The request a config describes; missing keys take their defaults. Throws ConfigError.
PredictionRequest request_from_config(const nlohmann::json& config);
/// A config document in any of the forms tocdlab writes: a bare config (to_config), the
/// output of `tocdlab predict --json` (its "config"), or what a run stores in
/// predictions.config_json: {"quantity", "step": config, "baseline": config}, whose T is the
/// step's T relative to the glass-only baseline's.
struct ConfigDocument {
  PredictionRequest step;
  std::optional<PredictionRequest> baseline;  ///< set for a T relative to a baseline
  std::string quantity;                       ///< what T means, as stored ("" for a bare config)
};
/// Reads any of those forms. Throws tocd::ConfigError naming what is wrong.
ConfigDocument config_document_from_json(const nlohmann::json& document);

/// The optics every region of a request's mesh gets: the threshold or graded model's, with
/// the slide's refractive index when slide_n is set.
mc::Optics optics_of(const PredictionRequest& request);
/// The same as stored in a prediction's config ("optics": region id -> optics). It is a
/// record, not an input: request_from_config refuses a config whose "optics" differ from it.
nlohmann::json optics_record(const PredictionRequest& request);

/// Checks ranges (displacement 0 <= d < thickness, photons > 0, known optics model and mesh
/// preset ...). Throws tocd::ConfigError naming the field.
void validate(const PredictionRequest& request);

/// Predicts transmission for compression steps. Caches FE solutions, composite meshes and
/// prepared Monte Carlo meshes keyed by their inputs, so a repeated step (or the same step
/// with other optics) skips FE and meshing. Thread contract: every member may be called from
/// any thread at once; concurrent requests for the same FE solution or mesh share one
/// computation. submit() queues the request on the predictor's own worker threads and
/// returns at once. The destructor finishes the queued requests.
///
/// With a `team` of several processes (MPI), predict() is a collective: every member calls
/// it with the same request, builds the step's mesh itself (the FE and TetGen are
/// deterministic), runs its share of the photons, and gets the same Prediction; only member
/// 0 writes fluence files.
class Predictor {
 public:
  /// `background`: the worker threads (and the Monte Carlo threads they start) run at the
  /// lowest scheduling priority (tocd::run_this_thread_in_background), for predictions made
  /// beside a recording: they must never cost the instruments' pollers a reading.
  explicit Predictor(int worker_threads = 1, parallel::Team* team = nullptr, bool background = false);
  ~Predictor();
  Predictor(const Predictor&) = delete;
  Predictor& operator=(const Predictor&) = delete;

  Prediction predict(const PredictionRequest& r);              // blocking
  std::future<Prediction> submit(const PredictionRequest& r);  // runs in the background

  /// Pieces of predict() for work shared out by batches (the distributed study): the exact
  /// Monte Carlo tallies of batches [first, last) of the request (this process alone), and
  /// the prediction from the tallies of all its batches summed (Tallies add element-wise).
  /// `mc_seconds` is reported as the Monte Carlo time. Writes fluence files when asked.
  mc::Tallies run_batches(const PredictionRequest& r, int first_batch, int last_batch);
  Prediction assemble(const PredictionRequest& r, const mc::Tallies& summed, double mc_seconds);

  struct CacheCounts {
    std::size_t fe_hits = 0, fe_misses = 0, mesh_hits = 0, mesh_misses = 0;
  };
  CacheCounts cache_counts() const;

 private:
  struct Impl;
  struct Staged;
  Staged stage(const PredictionRequest& r);
  void complete(const PredictionRequest& r, Staged& st, const mc::Result& res);
  std::unique_ptr<Impl> impl_;
  parallel::Team* team_ = nullptr;  ///< null: this process alone
  std::mutex queue_mutex_;
  std::condition_variable queue_cv_;
  std::deque<std::packaged_task<Prediction()>> queue_;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
  void work(bool background);
};

}  // namespace tocd::sim::study
