// The displacement history a recorded run hands to the biphasic FE, and the checks on a
// history request: cheap, no FE.
#include <string>

#include <gtest/gtest.h>

#include "tocd/core/error.hpp"
#include "tocd/sim/study/water_history.hpp"
#include "tocd/test/error_of.hpp"

namespace st = tocd::sim::study;

namespace {

std::string refusal(const st::WaterHistoryRequest& r) {
  return tocd::test::error_of<tocd::ConfigError>([&] { st::validate(r); });
}

st::WaterHistoryRequest ramp_and_hold() {
  st::WaterHistoryRequest r;
  r.history.t_s = {0, 1, 2, 10};
  r.history.d_mm = {0, 0, 0.5, 0.5};
  r.times_s = {0, 5, 10};
  return r;
}

TEST(WaterHistory, InterpolatesLinearlyAndHoldsPastTheEnds) {
  const auto h = ramp_and_hold().history;
  EXPECT_DOUBLE_EQ(h.at(-1), 0.0);
  EXPECT_DOUBLE_EQ(h.at(0.5), 0.0);
  EXPECT_DOUBLE_EQ(h.at(1.5), 0.25);
  EXPECT_DOUBLE_EQ(h.at(1.9), 0.45);
  EXPECT_DOUBLE_EQ(h.at(2), 0.5);
  EXPECT_DOUBLE_EQ(h.at(99), 0.5);
}

TEST(WaterHistory, RefusesHistoriesTheFeCannotFollow) {
  EXPECT_EQ(refusal(ramp_and_hold()), "");
  auto r = ramp_and_hold();
  r.history.d_mm[0] = 0.1;
  EXPECT_NE(refusal(r).find("pin on the surface"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.history.t_s[2] = 0.5;
  EXPECT_NE(refusal(r).find("ascending (knot 2)"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.history.d_mm[3] = 2.5;
  EXPECT_NE(refusal(r).find("depth 2.5 mm"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.history.d_mm.pop_back();
  EXPECT_NE(refusal(r).find("as many times as depths"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.times_s = {0, 11};
  EXPECT_NE(refusal(r).find("within the history [0, 10 s]"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.times_s = {5, 5};
  EXPECT_NE(refusal(r).find("ascending"), std::string::npos) << refusal(r);
  r = ramp_and_hold();
  r.drained_poisson = 0.5;
  EXPECT_NE(refusal(r).find("Poisson"), std::string::npos) << refusal(r);
}

}  // namespace
