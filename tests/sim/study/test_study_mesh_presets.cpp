// `fast` and `paper` meshes of the same step must agree on transmission within the Monte
// Carlo's statistics plus 1 % (the discretisation of the revolved surfaces).
#include <cmath>

#include <gtest/gtest.h>

#include "tocd/sim/study/predictor.hpp"

namespace st = tocd::sim::study;

TEST(StudyMeshPresets, FastAndPaperMeshesAgree) {
  st::Predictor predictor;
  for (double d : {0.0, 1.5}) {
    st::PredictionRequest r;
    r.displacement_mm = d;
    r.photons = 1000000;
    r.seed = 3;
    r.compressed_optics = st::native_skin_optics();
    r.mesh_preset = "fast";
    const auto fast = predictor.predict(r);
    r.mesh_preset = "paper";
    r.seed = 4;
    const auto paper = predictor.predict(r);
    std::printf("d %.3f: fast %.5f+-%.5f (%zu tets), paper %.5f+-%.5f (%zu tets)\n", d, fast.T, fast.T_stderr,
                fast.tets, paper.T, paper.T_stderr, paper.tets);
    EXPECT_GT(paper.tets, fast.tets);
    EXPECT_LT(std::abs(fast.T - paper.T), 3.0 * std::hypot(fast.T_stderr, paper.T_stderr) + 0.01 * paper.T)
        << d;
  }
}
