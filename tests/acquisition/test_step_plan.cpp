#include <gtest/gtest.h>

#include "tocd/acquisition/step_plan.hpp"
#include "tocd/core/error.hpp"

using namespace tocd::acquisition;

TEST(StepPlan, NominalStrainIsDisplacementOverThickness) {
  EXPECT_DOUBLE_EQ(nominal_strain(1.25, 2.5), 0.5);
  EXPECT_THROW(nominal_strain(1.0, 0.0), tocd::ConfigError);
}

TEST(StepPlan, LinearStepsIncludeBothEnds) {
  const auto steps = linear_steps(0.0, 1.5, 7);
  ASSERT_EQ(steps.size(), 7u);
  EXPECT_DOUBLE_EQ(steps.front(), 0.0);
  EXPECT_DOUBLE_EQ(steps[1], 0.25);
  EXPECT_DOUBLE_EQ(steps.back(), 1.5);
  EXPECT_THROW(linear_steps(0.0, 1.0, 0), tocd::ConfigError);
}
