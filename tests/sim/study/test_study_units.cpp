// Unit tests of the study's own logic: caches, point location and slices, graded optics,
// the FE -> profile adapter, configs, the study table.
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/mesh/slab_mesh.hpp"
#include "tocd/sim/study/fluence_slices.hpp"
#include "tocd/sim/study/keyed_cache.hpp"
#include "tocd/sim/study/predictor.hpp"
#include "tocd/sim/study/profile_adapter.hpp"
#include "tocd/sim/study/study.hpp"
#include "tocd/sim/study/study_optics.hpp"
#include "tocd/test/temp_dir.hpp"

namespace st = tocd::sim::study;
namespace msh = tocd::sim::mesh;
namespace mc = tocd::sim::mc;

namespace {

msh::TetMesh slab(int cells = 6) {
  msh::SlabSpec spec;
  spec.width_mm = spec.depth_mm = 4.0;
  spec.cells_x = spec.cells_y = cells;
  spec.layers = {{1.0, 4, 3}, {1.0, 2, 3}};  // skin over slide, z from 0 to 2
  return msh::make_slab(spec);
}

msh::Point3 centroid(const msh::TetMesh& m, std::size_t t) {
  msh::Point3 c{0, 0, 0};
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 3; ++k) c[k] += 0.25 * m.nodes[static_cast<std::size_t>(m.tets[t][v])][k];
  return c;
}

}  // namespace

TEST(StudyKeyedCache, ComputesOnceAndCountsHits) {
  st::KeyedCache<int> cache(4);
  int calls = 0;
  auto a = cache.get_or_compute("a", [&] { return ++calls * 10; });
  auto b = cache.get_or_compute("a", [&] { return ++calls * 10; });
  EXPECT_FALSE(a.hit);
  EXPECT_TRUE(b.hit);
  EXPECT_EQ(*b.value, 10);
  EXPECT_EQ(a.value.get(), b.value.get());
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(cache.hits(), 1u);
  EXPECT_EQ(cache.misses(), 1u);
}

TEST(StudyKeyedCache, ForgetsLeastRecentlyUsed) {
  st::KeyedCache<int> cache(2);
  cache.get_or_compute("a", [] { return 1; });
  cache.get_or_compute("b", [] { return 2; });
  cache.get_or_compute("a", [] { return 1; });  // a is now the most recent
  cache.get_or_compute("c", [] { return 3; });  // evicts b
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_TRUE(cache.get_or_compute("a", [] { return -1; }).hit);
  EXPECT_FALSE(cache.get_or_compute("b", [] { return 2; }).hit);
}

TEST(StudyKeyedCache, FailedComputationIsNotKept) {
  st::KeyedCache<int> cache(2);
  EXPECT_THROW(cache.get_or_compute("a", []() -> int { throw tocd::Error("boom"); }), tocd::Error);
  auto again = cache.get_or_compute("a", [] { return 5; });
  EXPECT_FALSE(again.hit);
  EXPECT_EQ(*again.value, 5);
}

TEST(StudyKeyedCache, ConcurrentCallersShareOneComputation) {
  st::KeyedCache<int> cache(4);
  std::atomic<int> calls{0};
  std::atomic<bool> go{false};
  std::vector<std::thread> threads;
  std::vector<int> seen(6, 0);
  for (int i = 0; i < 6; ++i)
    threads.emplace_back([&, i] {
      while (!go) std::this_thread::yield();
      seen[static_cast<std::size_t>(i)] =
          *cache
               .get_or_compute("k",
                               [&] {
                                 ++calls;
                                 std::this_thread::sleep_for(std::chrono::milliseconds(50));
                                 return 42;
                               })
               .value;
    });
  go = true;
  for (auto& t : threads) t.join();
  EXPECT_EQ(calls.load(), 1);
  for (int v : seen) EXPECT_EQ(v, 42);
}

TEST(StudyTetLocator, FindsTheTetOfEveryCentroidAndNothingOutside) {
  const auto m = slab();
  const st::TetLocator loc(m);
  for (std::size_t t = 0; t < m.tets.size(); ++t)
    ASSERT_EQ(loc.find(centroid(m, t)), static_cast<std::int32_t>(t));
  EXPECT_EQ(loc.find({0.0, 0.0, 2.5}), -1);
  EXPECT_EQ(loc.find({2.1, 0.0, 1.0}), -1);
  EXPECT_EQ(loc.find({0.0, 0.0, -0.01}), -1);
  // Points on nodes, edges and faces are found (in one of the tets sharing them).
  EXPECT_GE(loc.find({0.0, 0.0, 1.0}), 0);
  EXPECT_GE(loc.find({-2.0, -2.0, 0.0}), 0);
  EXPECT_GE(loc.find({2.0, 2.0, 2.0}), 0);
}

TEST(StudyFluenceSlices, SampleTheTetValuesOnTheGrid) {
  const auto m = slab();
  const st::TetLocator loc(m);
  mc::Result r;
  r.fluence_per_tet.resize(m.tets.size());
  r.fluence_per_tet_se.resize(m.tets.size());
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    r.fluence_per_tet[t] = centroid(m, t)[2];  // rises with height: slices can be checked against z
    r.fluence_per_tet_se[t] = 0.01;
  }
  const auto box = msh::bounding_box(m);
  const auto grids = st::standard_slices(box, 1.5, 0.25);
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[0].nu, 17);
  EXPECT_EQ(grids[1].nv, 9);
  const auto h = st::sample_slice(m, loc, r, grids[0]);
  ASSERT_EQ(h.size(), 17u * 17u);
  for (const auto& s : h) {
    ASSERT_GE(s.tet, 0);
    EXPECT_EQ(s.region, 4);                  // z = 1.5 lies in the upper layer
    EXPECT_NEAR(s.fluence, 1.5, 1.0 / 3.0);  // a tet's centroid is within a cell height of the point
  }
  const auto v = st::sample_slice(m, loc, r, grids[1]);
  for (const auto& s : v) {
    ASSERT_GE(s.tet, 0);
    EXPECT_DOUBLE_EQ(s.p[1], 0.0);
    EXPECT_EQ(s.region, s.p[2] > 1.0 + 1e-9 ? 4 : (s.p[2] < 1.0 - 1e-9 ? 2 : s.region));
  }
  const tocd::test::TempDir dir("study_slice_test");
  st::write_slice_csv(v, dir / "v.csv");
  std::ifstream in(dir / "v.csv");
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(header, "x_mm,y_mm,z_mm,region,fluence,fluence_se");
  EXPECT_EQ(first.rfind("-2,0,0,2,", 0), 0u) << first;
}

TEST(StudyFluenceSlices, OutsidePointsAreEmptyAndMissingTalliesAreAnError) {
  const auto m = slab(2);
  const st::TetLocator loc(m);
  mc::Result r;
  EXPECT_THROW(st::sample_slice(m, loc, r, st::standard_slices(msh::bounding_box(m), 1.0)[0]), tocd::Error);
  r.fluence_per_tet.assign(m.tets.size(), 1.0);
  r.fluence_per_tet_se.assign(m.tets.size(), 0.0);
  st::SliceGrid g{"out", {0, 0, 3.0}, {0.1, 0, 0}, {0, 0.1, 0}, 2, 2};
  const auto s = st::sample_slice(m, loc, r, g);
  for (const auto& p : s) {
    EXPECT_EQ(p.tet, -1);
    EXPECT_TRUE(std::isnan(p.fluence));
  }
  EXPECT_THROW(st::standard_slices(msh::bounding_box(m), 1.0, 0.0), tocd::ConfigError);
}

TEST(StudyGradedOptics, LevelsAndInterpolation) {
  st::GradedOptics g;  // 8 bins, fully cleared at log strain -0.5
  EXPECT_EQ(st::graded_level(0.0, g), 0);
  EXPECT_EQ(st::graded_level(0.1, g), 0);  // tension stays native
  EXPECT_EQ(st::graded_level(-0.03, g), 0);
  EXPECT_EQ(st::graded_level(-0.25, g), 4);
  EXPECT_EQ(st::graded_level(-0.5, g), 8);
  EXPECT_EQ(st::graded_level(-1.2, g), 8);
  EXPECT_EQ(st::graded_level(std::nan(""), g), 0);
  const auto half = st::graded_optics_at(0.5, g);
  EXPECT_NEAR(half.mu_a_per_mm, 0.5 * (0.089 + 0.0534), 1e-12);
  EXPECT_NEAR(half.mu_s_per_mm, 0.5 * (28.9 + 17.34), 1e-12);
  EXPECT_NEAR(half.n, 0.5 * (1.38 + 1.518), 1e-12);
  EXPECT_DOUBLE_EQ(half.g, 0.926);
  const auto optics = st::graded_optics(g);
  EXPECT_EQ(optics.regions.count(5), 0u);
  EXPECT_EQ(optics.regions.size(), 4u + 8u);
  EXPECT_DOUBLE_EQ(optics.regions.at(st::kGradedRegionBase + 8).mu_a_per_mm, 0.0534);
  g.bins = 0;
  EXPECT_THROW(st::graded_level(-0.1, g), tocd::ConfigError);
}

TEST(StudyGradedOptics, AssignsSkinTetsByCentroidStrain) {
  auto m = slab();
  st::GradedOptics g;
  g.bins = 4;
  // Strain falls linearly with height through the skin layer (z 1..2): -0.5 at the top.
  const auto counts = st::assign_graded_regions(m, g, [](double, double z) { return -0.5 * (z - 1.0); });
  std::size_t total = 0;
  for (auto c : counts) total += c;
  std::size_t skin_tets = 0, slide_tets = 0;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    const int region = m.regions[t];
    if (region == 2) {
      ++slide_tets;
      continue;
    }
    ++skin_tets;
    const double z = centroid(m, t)[2];
    const int level = static_cast<int>(std::lround((z - 1.0) * 4));
    EXPECT_EQ(region, level == 0 ? 4 : st::kGradedRegionBase + level) << "z " << z;
  }
  EXPECT_EQ(total, skin_tets);
  EXPECT_EQ(slide_tets, m.tets.size() - skin_tets);
}

TEST(StudyProfileAdapter, TidiesTheFeOutlines) {
  tocd::sim::fe::FeStepResult step;
  step.displacement_mm = 1.0;
  step.top_surface = {{0.0, 1.5}, {0.0, 1.5}, {0.5, 1.6}, {0.4, 1.6}, {1.0, 2.0}, {6.25, 2.5}};
  // Clockwise square with a repeated closing point, a degenerate sliver and a 2-point line.
  step.compressed_outlines = {
      {{0, 0}, {0, 1}, {1, 1}, {1, 0}, {0, 0}}, {{0, 0}, {1, 0}, {2, 0}}, {{0, 0}, {1, 1}}};
  const auto p = st::to_skin_profile(step, 2.5);
  EXPECT_DOUBLE_EQ(p.thickness_mm, 2.5);
  ASSERT_EQ(p.top_surface.size(), 4u);
  for (std::size_t i = 1; i < p.top_surface.size(); ++i)
    EXPECT_GT(p.top_surface[i].r_mm, p.top_surface[i - 1].r_mm);
  ASSERT_EQ(p.compressed_outlines.size(), 1u);
  const auto& sq = p.compressed_outlines[0];
  ASSERT_EQ(sq.size(), 4u);
  double area = 0;
  for (std::size_t i = 0; i < sq.size(); ++i) {
    const auto& a = sq[i];
    const auto& b = sq[(i + 1) % sq.size()];
    area += a.r_mm * b.z_mm - b.r_mm * a.z_mm;
  }
  EXPECT_NEAR(0.5 * area, 1.0, 1e-12);  // now counter-clockwise
  tocd::sim::fe::FeStepResult empty;
  EXPECT_THROW(st::to_skin_profile(empty, 2.5), tocd::Error);
  // A surface starting off-axis gets a point on the axis.
  step.top_surface = {{0.2, 1.5}, {6.25, 2.5}};
  const auto q = st::to_skin_profile(step, 2.5);
  ASSERT_EQ(q.top_surface.size(), 3u);
  EXPECT_DOUBLE_EQ(q.top_surface[0].r_mm, 0.0);
}

TEST(StudyProfileAdapter, KeepsOutlinesAlongTheContactSurface) {
  tocd::sim::fe::FeStepResult step;
  step.top_surface = {{0.0, 1.0}, {0.5, 1.1}, {1.0, 1.4}, {6.25, 2.5}};
  // Compressed zone under the pin: up the axis to the surface, along it, down, back. The
  // geometry takes the skin top as its boundary there, so the points stay where they are.
  const std::vector<tocd::sim::fe::Point2> outline{{0.0, 0.0}, {1.0, 0.0},  {1.0, 1.4}, {0.5, 1.1},
                                                   {0.0, 1.0}, {0.0, 0.98}, {0.0, 0.5}};
  step.compressed_outlines = {outline};
  const auto p = st::to_skin_profile(step, 2.5);
  ASSERT_EQ(p.compressed_outlines.size(), 1u);
  const auto& o = p.compressed_outlines[0];
  ASSERT_EQ(o.size(), outline.size());
  for (std::size_t i = 0; i < o.size(); ++i) {
    EXPECT_DOUBLE_EQ(o[i].r_mm, outline[i].r_mm) << i;
    EXPECT_DOUBLE_EQ(o[i].z_mm, outline[i].z_mm) << i;
  }
}

TEST(StudyConfig, RoundTripsAndRejectsBadRequests) {
  st::PredictionRequest r;
  r.displacement_mm = 0.8;
  r.thickness_mm = 1.5;
  r.optics_model = "graded";
  r.graded.bins = 5;
  r.photons = 1234;
  r.seed = 99;
  r.compressed_optics = {0.05, 20.0, 0.926, 1.45, "x"};
  const auto j = st::to_config(r);
  const auto back = st::request_from_config(j);
  EXPECT_EQ(st::to_config(back), j);
  EXPECT_EQ(back.graded.bins, 5);
  EXPECT_EQ(back.material.mu, r.material.mu);

  auto bad = [](auto change) {
    st::PredictionRequest q;
    change(q);
    return q;
  };
  EXPECT_THROW(st::validate(bad([](auto& q) { q.displacement_mm = 3.0; })), tocd::ConfigError);
  EXPECT_THROW(st::validate(bad([](auto& q) { q.thickness_mm = -1; })), tocd::ConfigError);
  EXPECT_THROW(st::validate(bad([](auto& q) { q.optics_model = "magic"; })), tocd::ConfigError);
  EXPECT_THROW(st::validate(bad([](auto& q) { q.mesh_preset = "huge"; })), tocd::ConfigError);
  EXPECT_THROW(st::validate(bad([](auto& q) { q.photons = 0; })), tocd::ConfigError);
  EXPECT_THROW(st::validate(bad([](auto& q) { q.compressed_optics.n = -1; })), tocd::ConfigError);
  try {
    st::validate(bad([](auto& q) { q.displacement_mm = 3.0; }));
  } catch (const tocd::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("displacement_mm"), std::string::npos);
  }
  EXPECT_THROW(st::request_from_config(nlohmann::json{{"photons", "many"}}), tocd::ConfigError);
  EXPECT_THROW(st::request_from_config(nlohmann::json::array()), tocd::ConfigError);
}

// Found by the predict_config fuzz target: nlohmann's get<> wrapped -1 photons to 2^64 - 1 and
// converted a seed beyond 2^64 (read as a double) with undefined behaviour.
TEST(PredictionConfig, WholeNumbersMustBeWholeAndInRange) {
  using nlohmann::json;
  const auto error_of = [](const json& j) {
    try {
      (void)st::request_from_config(j);
    } catch (const tocd::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error_of(json{{"photons", -1}}).find("photons must be a whole number from 1 to 1000000000000"),
            std::string::npos);
  EXPECT_NE(error_of(json::parse(R"({"seed": 18446744073709551616})")).find("seed"), std::string::npos);
  EXPECT_NE(error_of(json{{"batches", 1e300}}).find("batches"), std::string::npos);
  EXPECT_NE(error_of(json{{"batches", 2.5}}).find("batches"), std::string::npos);
  EXPECT_EQ(st::request_from_config(json{{"photons", 2000.0}}).photons, 2000u);
  EXPECT_EQ(st::request_from_config(json::parse(R"({"seed": 18446744073709551615})")).seed, UINT64_MAX);
}

TEST(PredictionConfig, DocumentsInEveryFormTocdlabWritesAreRead) {
  st::PredictionRequest step;
  step.displacement_mm = 0.5;
  step.seed = 7;
  st::PredictionRequest base = step;
  base.baseline = true;
  base.seed = 8;
  const auto bare = st::config_document_from_json(st::to_config(step));
  EXPECT_EQ(st::to_config(bare.step), st::to_config(step));
  EXPECT_FALSE(bare.baseline.has_value());
  // `predict --json` output: the config under "config".
  const auto output = st::config_document_from_json({{"T", 0.3}, {"config", st::to_config(step)}});
  EXPECT_EQ(st::to_config(output.step), st::to_config(step));
  // What a run stores: the step and its glass-only baseline, each a whole config.
  const nlohmann::json stored = {{"quantity", "T(step) / T(glass-only baseline)"},
                                 {"step", st::to_config(step)},
                                 {"baseline", st::to_config(base)}};
  const auto relative = st::config_document_from_json(stored);
  EXPECT_EQ(st::to_config(relative.step), st::to_config(step));
  ASSERT_TRUE(relative.baseline.has_value());
  EXPECT_TRUE(relative.baseline->baseline);
  EXPECT_EQ(relative.baseline->seed, 8u);
  EXPECT_EQ(relative.quantity, "T(step) / T(glass-only baseline)");
  // ... and the same wrapped in a relative prediction's own --json output.
  EXPECT_EQ(st::config_document_from_json({{"config", stored}}).baseline->seed, 8u);
  EXPECT_THROW(st::config_document_from_json({{"step", st::to_config(step)}, {"baseline", true}}),
               tocd::ConfigError);
  EXPECT_THROW(st::config_document_from_json({{"step", "x"}}), tocd::ConfigError);
}

TEST(StudyCases, PaperCasesFollowTheModelNote) {
  st::StudySettings s;
  const auto cases = st::paper_cases(s);
  ASSERT_EQ(cases.size(), 12u);
  EXPECT_TRUE(cases[0].request.baseline);
  const double d[] = {0, 0, 0.625, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5, 1.5};
  const double mua[] = {0, 0.089, 0.089, 0.089, 0.0712, 0.0534, 0.089, 0.089, 0.089, 0.089, 0.0712, 0.0534};
  const double mus[] = {0, 28.9, 28.9, 28.9, 28.9, 28.9, 23.12, 17.34, 28.9, 28.9, 23.12, 17.34};
  const double n[] = {0, 1.38, 1.38, 1.38, 1.38, 1.38, 1.38, 1.38, 1.449, 1.518, 1.449, 1.518};
  for (int i = 1; i < 12; ++i) {
    const auto& c = cases[static_cast<std::size_t>(i)];
    EXPECT_EQ(c.id, i);
    EXPECT_FALSE(c.request.baseline);
    EXPECT_DOUBLE_EQ(c.request.displacement_mm, d[i]);
    EXPECT_NEAR(c.request.compressed_optics.mu_a_per_mm, mua[i], 1e-12) << i;
    EXPECT_NEAR(c.request.compressed_optics.mu_s_per_mm, mus[i], 1e-12) << i;
    EXPECT_NEAR(c.request.compressed_optics.n, n[i], 1e-12) << i;
    EXPECT_DOUBLE_EQ(c.request.compressed_optics.g, 0.926);
  }
  const auto sweep = st::sweep_cases(s, {0.5, 1.0}, {1.5, 2.5}, {"native", "graded", "0.05/20/1.4"});
  EXPECT_EQ(sweep.size(), 1u + 2 * 2 * 3);
  EXPECT_EQ(sweep.back().request.optics_model, "threshold");
  EXPECT_DOUBLE_EQ(sweep.back().request.compressed_optics.n, 1.4);
  EXPECT_EQ(sweep[2].request.optics_model, "graded");
  EXPECT_THROW(st::sweep_cases(s, {0.5}, {}, {"bogus"}), tocd::ConfigError);
  EXPECT_THROW(st::sweep_cases(s, {2.0}, {1.5}, {}), tocd::ConfigError);
  EXPECT_THROW(st::sweep_cases(s, {}, {}, {}), tocd::ConfigError);
}

TEST(StudyTableOutput, RelativesJsonAndCsv) {
  st::StudyTable t;
  auto row = [](int id, double T, double se) {
    st::StudyRow r;
    r.c.id = id;
    r.c.optics_label = "native";
    r.p.T = T;
    r.p.T_stderr = se;
    r.p.tets = 1000;
    return r;
  };
  t.rows = {row(0, 0.8, 0.004), row(3, 0.2, 0.002), row(4, 0.25, 0.002)};
  st::fill_relatives(t);
  EXPECT_DOUBLE_EQ(t.rows[2].rel_a, 0.25 / 0.8);
  EXPECT_DOUBLE_EQ(t.rows[2].rel_b, 1.25);
  EXPECT_NEAR(t.rows[2].rel_b_se, 1.25 * std::hypot(0.002 / 0.25, 0.002 / 0.2), 1e-15);
  EXPECT_DOUBLE_EQ(t.rows[1].rel_b_se, 0.0);
  const auto j = st::to_json(t);
  ASSERT_EQ(j["simulations"].size(), 3u);
  EXPECT_DOUBLE_EQ(j["simulations"][2]["T_rel_b"].get<double>(), 1.25);
  EXPECT_DOUBLE_EQ(j["simulations"][2]["T_se"].get<double>(), 0.002);
  const std::string csv = st::to_csv(t);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  const std::string text = st::format_table(t);
  EXPECT_NE(text.find("1.2500"), std::string::npos);
  t.ref_b = 7;  // absent: relative columns empty
  st::fill_relatives(t);
  EXPECT_TRUE(std::isnan(t.rows[0].rel_b));
  EXPECT_TRUE(st::to_json(t)["simulations"][0]["T_rel_b"].is_null());
}
