#include "trueaxis/runtime/output_shaper.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace trueaxis::runtime {
namespace {

TEST(OutputShaper, StepIsRateLimitedAndReachesTarget) {
  OutputShaperOptions o;
  o.max_step_um = 0.5;
  o.max_correction_um = 100;
  OutputShaperState s;
  const double q = 0.1;
  int cycles = 0;
  double prev = 0;
  while (OutputUm(s, q) < 20 - 1e-9 && cycles < 1000) {
    s = ShapeOutput(s, 20.0, q, o);
    EXPECT_LE(std::fabs(OutputUm(s, q) - prev), o.max_step_um + 1e-9);
    prev = OutputUm(s, q);
    ++cycles;
  }
  EXPECT_NEAR(OutputUm(s, q), 20.0, 1e-9);
  EXPECT_GE(cycles, 40);  // 20 µm at 0.5 µm/cycle cannot take fewer than 40 cycles
}

TEST(OutputShaper, BoundHoldsForHugeAndInfiniteDemands) {
  OutputShaperOptions o;
  o.max_step_um = 10;
  o.max_correction_um = 25;
  OutputShaperState s;
  for (int i = 0; i < 100; ++i) s = ShapeOutput(s, i % 2 ? 1e9 : std::numeric_limits<double>::infinity(), 1.0, o);
  EXPECT_DOUBLE_EQ(OutputUm(s, 1.0), 25.0);
  for (int i = 0; i < 100; ++i) s = ShapeOutput(s, -std::numeric_limits<double>::infinity(), 1.0, o);
  EXPECT_DOUBLE_EQ(OutputUm(s, 1.0), -25.0);
}

TEST(OutputShaper, NanHoldsTheOutput) {
  OutputShaperOptions o;
  OutputShaperState s;
  for (int i = 0; i < 20; ++i) s = ShapeOutput(s, 7.0, 1.0, o);
  const auto before = s;
  for (int i = 0; i < 20; ++i) s = ShapeOutput(s, std::nan(""), 1.0, o);
  EXPECT_EQ(s.counts, before.counts);
  EXPECT_EQ(s.ramp_um, before.ramp_um);
}

TEST(OutputShaper, OutputIsAlwaysAWholeNumberOfQuanta) {
  OutputShaperOptions o;
  o.max_step_um = 0.37;
  const double q = 0.25;
  OutputShaperState s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-30, 30);
  for (int i = 0; i < 2000; ++i) {
    s = ShapeOutput(s, d(rng), q, o);
    const double out = OutputUm(s, q);
    EXPECT_NEAR(out / q, std::round(out / q), 1e-12);
  }
}

// A value sitting on a rounding boundary with noise must not make the output toggle.
int CountToggles(double hysteresis) {
  OutputShaperOptions o;
  o.max_step_um = 5;
  o.hysteresis = hysteresis;
  const double q = 1.0;
  OutputShaperState s;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> noise(-0.2, 0.2);
  for (int i = 0; i < 50; ++i) s = ShapeOutput(s, 3.5, q, o);
  int toggles = 0;
  auto last = s.counts;
  for (int i = 0; i < 1000; ++i) {
    s = ShapeOutput(s, 3.5 + noise(rng), q, o);
    if (s.counts != last) ++toggles;
    last = s.counts;
  }
  return toggles;
}

TEST(OutputShaper, HysteresisPreventsLimitCycling) {
  EXPECT_GT(CountToggles(0.0), 100);  // without hysteresis the output chatters
  EXPECT_EQ(CountToggles(0.25), 0);
}

TEST(OutputShaper, HysteresisStillTracksWithinOneQuantum) {
  OutputShaperOptions o;
  o.max_step_um = 0.05;
  const double q = 1.0;
  OutputShaperState s;
  // slow ramp: the output follows with at most (0.5 + h) quanta of error
  for (int i = 0; i < 2000; ++i) {
    const double target = 0.01 * i;
    s = ShapeOutput(s, target, q, o);
    EXPECT_LE(std::fabs(OutputUm(s, q) - s.ramp_um), (0.5 + o.hysteresis) * q + 1e-9);
  }
}

TEST(OutputShaper, InvariantsUnderRandomDemands) {
  OutputShaperOptions o;
  o.max_step_um = 0.8;
  o.max_correction_um = 40;
  const double q = 0.5;
  OutputShaperState s;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> d(-200, 200);
  std::bernoulli_distribution nan(0.05);
  double prev = 0;
  for (int i = 0; i < 20000; ++i) {
    s = ShapeOutput(s, nan(rng) ? std::nan("") : d(rng), q, o);
    const double out = OutputUm(s, q);
    ASSERT_LE(std::fabs(out - prev), std::max(q, o.max_step_um) + 1e-9);
    ASSERT_LE(std::fabs(out), o.max_correction_um + 1e-9);
    prev = out;
  }
}

TEST(OutputShaper, StepSmallerThanQuantumMovesOneCountAtATime) {
  OutputShaperOptions o;
  o.max_step_um = 0.1;
  const double q = 1.0;
  OutputShaperState s;
  double prev = 0;
  for (int i = 0; i < 300; ++i) {
    s = ShapeOutput(s, 10, q, o);
    EXPECT_LE(std::fabs(OutputUm(s, q) - prev), q + 1e-12);
    prev = OutputUm(s, q);
  }
  EXPECT_DOUBLE_EQ(prev, 10);
}

TEST(OutputShaper, OptionsValidation) {
  OutputShaperOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why));
  o.max_step_um = 0;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("max_step_um"), std::string::npos);
  o = {};
  o.hysteresis = 0.7;
  EXPECT_FALSE(o.IsValid(&why));
  o = {};
  o.max_correction_um = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace trueaxis::runtime
