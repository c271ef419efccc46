// The campaign's warm-up rule, shared by the virtual machine's campaign and `campaign log`.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "trueaxis/sim/warmup_rule.hpp"

namespace trueaxis::sim {
namespace {

// A first-order warm-up to `rise` °C with time constant tau, sampled every `dt` s up to `t_end`.
WarmUpCurve FirstOrder(double rise, double tau, double dt, double t_end) {
  WarmUpCurve c;
  for (double t = dt; t <= t_end; t += dt) c.emplace_back(t, rise * (1 - std::exp(-t / tau)));
  return c;
}

TEST(WarmUpRule, StepsGrowWithTheRiseAndShareWhatIsStillToCome) {
  WarmUpRule rule;  // 0.5 °C, 25 %, 16 tests
  EXPECT_DOUBLE_EQ(NextTestRise(rule, {}, 0, 0), 0.5);
  // Before the curve bends: the larger of 0.5 °C and 25 % of the rise.
  EXPECT_DOUBLE_EQ(NextTestRise(rule, {}, 1.0, 1), 1.5);
  EXPECT_DOUBLE_EQ(NextTestRise(rule, {}, 4.0, 2), 5.0);
  // A curve that bends towards +20 °C: the three-point formula finds it, and after 12 tests the 3
  // left (one kept for saturation) share the 12 °C still to come (more than 25 % of 7.9 °C).
  const auto curve = FirstOrder(20, 3600, 10, 1800 * 1.0);
  const double rise = curve.back().second;
  EXPECT_NEAR(EstimateSaturationRise(curve), 20, 0.2);
  EXPECT_NEAR(NextTestRise(rule, curve, rise, 12), rise + (20 - rise) / 4, 0.05);
  EXPECT_NEAR(NextTestRise(rule, curve, rise, 2), rise * 1.25, 1e-9) << "many tests left: 25 % of the rise";
  EXPECT_TRUE(ThresholdTestAllowed(rule, 14));
  EXPECT_FALSE(ThresholdTestAllowed(rule, 15)) << "the last test is kept for saturation";
}

TEST(WarmUpRule, SaturatedWhenTheNutSettledOverTheWindow) {
  WarmUpRule rule;  // 0.15 °C in 30 min
  std::vector<double> nut;
  for (int i = 0; i < 60; ++i) nut.push_back(30 + 0.1 * i / 60);  // 0.1 °C over 30 min, every 30 s
  EXPECT_FALSE(WarmUpSaturated(rule, nut, 30)) << "not yet 30 min";
  nut.push_back(30.1);
  EXPECT_TRUE(WarmUpSaturated(rule, nut, 30));
  nut.push_back(30.4);
  EXPECT_FALSE(WarmUpSaturated(rule, nut, 30));
}

}  // namespace
}  // namespace trueaxis::sim
