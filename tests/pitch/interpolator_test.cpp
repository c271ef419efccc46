// The interpolator of the virtual CNC: the correction applied ahead of the
// motion (seed 002) against the naive one-interval-late variant.
#include <gtest/gtest.h>

#include <cmath>

#include "pitch_test_machine.hpp"
#include "trueaxis/sim/interpolator.hpp"

namespace trueaxis::sim {
namespace {

// A correction with a known slope: A·sin(2πx/λ), max slope 2πA/λ µm/mm.
constexpr double kA = 3, kLambda = 5;
double Wave(double x, int) { return kA * std::sin(2 * M_PI * x / kLambda); }

MoveStats Move(FeedForward mode, double feed, double cycle_s) {
  VirtualMachine vm(pitch::testing::PitchMachine(), 3);
  InterpolatorOptions o;
  o.mode = mode;
  o.cycle_s = cycle_s;
  CncInterpolator ipo(vm, 0, o, Wave);
  ipo.MoveTo(10, 2000);
  return ipo.MoveTo(110, feed);
}

TEST(Interpolator, AheadLeavesOnlyTheChordErrorLateLagsOneInterval) {
  for (double cycle : {0.001, 0.004}) {
    for (double feed : {5000.0, 20000.0}) {
      const MoveStats ahead = Move(FeedForward::kAhead, feed, cycle);
      const MoveStats late = Move(FeedForward::kLate, feed, cycle);
      const double step_mm = feed / 60 * cycle;
      const double slope = 2 * M_PI * kA / kLambda;
      // Late: about one interval of slope (the worst sub-step sees the whole interval).
      EXPECT_NEAR(late.max_abs_following_um, slope * step_mm, 0.15 * slope * step_mm) << feed << " " << cycle;
      // Ahead: the chord of the curve over one interval, A·k²·step²/8.
      const double k = 2 * M_PI / kLambda;
      EXPECT_LE(ahead.max_abs_following_um, kA * k * k * step_mm * step_mm / 8 * 1.05 + 1e-9) << feed << " " << cycle;
      EXPECT_LT(ahead.max_abs_following_um, 0.3 * late.max_abs_following_um);
      EXPECT_GT(ahead.cycles, 0u);
    }
  }
}

// A table four times per lead of a 5 mm screw (knots every 1.25 mm, a lead
// harmonic of 6 µm) at 40 m/min: a 2 ms interpolation cycle spans 1.33 mm, more
// than a knot interval. Ahead evaluates the table at every fine step of the
// drive, so the correction still follows within 1 µm (per cycle alone the chord
// between set points cut the knots: several µm); late lags by a whole cycle.
TEST(Interpolator, AheadFollowsAFineTableAtFortyMetresAMinute) {
  auto table = [](double x, int) {
    const double knot = 1.25;
    const double k = std::floor(x / knot), f = x / knot - k;
    auto at = [](double xk) { return 6 * std::sin(2 * M_PI * xk / 5); };
    return at(k * knot) * (1 - f) + at((k + 1) * knot) * f;
  };
  auto run = [&](FeedForward mode) {
    VirtualMachine vm(pitch::testing::PitchMachine(), 3);
    InterpolatorOptions o;
    o.mode = mode;
    CncInterpolator ipo(vm, 0, o, table);
    ipo.MoveTo(10, 2000);
    return ipo.MoveTo(120, 40000);
  };
  const MoveStats ahead = run(FeedForward::kAhead), late = run(FeedForward::kLate);
  EXPECT_LE(ahead.max_abs_following_um, 1.0);
  EXPECT_GT(late.max_abs_following_um, 5.0);
}

TEST(Interpolator, FollowingErrorOfLateGrowsWithFeed) {
  const double slow = Move(FeedForward::kLate, 2000, 0.002).max_abs_following_um;
  const double fast = Move(FeedForward::kLate, 20000, 0.002).max_abs_following_um;
  EXPECT_NEAR(fast / slow, 10, 1.5);
}

TEST(Interpolator, TheMachineReallyArrivesWhereTheTruthSays) {
  // With the machine's own error (truth) as the table, ahead puts the table
  // on target while moving; late is off by the lag; off shows the raw error.
  auto run = [](FeedForward mode) {
    VirtualMachine vm(pitch::testing::PitchMachine(), 3);
    InterpolatorOptions o;
    o.mode = mode;
    const VirtualMachine* p = &vm;
    CncInterpolator ipo(vm, 0, o, [p](double x, int dir) { return -p->ErrorAtUm(0, x, dir); });
    ipo.MoveTo(10, 2000);
    return ipo.MoveTo(110, 30000).max_abs_position_error_um;
  };
  const double off = run(FeedForward::kOff), ahead = run(FeedForward::kAhead), late = run(FeedForward::kLate);
  // Ahead leaves the chord error of the lead harmonics over one 1 mm interval
  // (30 m/min, 2 ms): Σ A_h·(2πh/L)²·s²/8 = 0.39 + 0.47 µm for 2.0 / 0.6 µm at L = 5 mm.
  const double k = 2 * M_PI / 5, s = 1.0;
  const double chord = (2.0 * k * k + 0.6 * 4 * k * k) * s * s / 8;
  EXPECT_GT(off, 10);
  EXPECT_LT(ahead, chord + 0.1);
  EXPECT_GT(late, 2 * ahead);
}

TEST(Interpolator, LateSwitchesTheDirectionOneIntervalAfterTheReversal) {
  // A pure direction-dependent correction: +2 µm forward, −2 µm reverse.
  auto run = [](FeedForward mode) {
    VirtualMachine vm(pitch::testing::PitchMachine(), 3);
    InterpolatorOptions o;
    o.mode = mode;
    o.fine_steps = 1;
    CncInterpolator ipo(vm, 0, o, [](double, int dir) { return dir > 0 ? 2.0 : -2.0; });
    ipo.MoveTo(50, 5000);
    return ipo.MoveTo(20, 5000);  // reversal
  };
  const MoveStats ahead = run(FeedForward::kAhead), late = run(FeedForward::kLate);
  EXPECT_NEAR(ahead.max_abs_following_um, 0, 1e-12);  // switched with the first interval of the new direction
  EXPECT_NEAR(late.max_abs_following_um, 4, 1e-12);   // still the forward value for one interval
}

TEST(Interpolator, DwellBringsLateToTheCorrectionOfThePositionReached) {
  VirtualMachine vm(pitch::testing::PitchMachine(), 3);
  InterpolatorOptions o;
  o.mode = FeedForward::kLate;
  CncInterpolator ipo(vm, 0, o, Wave);
  ipo.MoveTo(31.3, 10000);
  EXPECT_GT(std::abs(vm.CorrectionUm(0) - Wave(31.3, 1)), 0.05);
  ipo.Dwell(0.5);
  EXPECT_NEAR(vm.CorrectionUm(0), Wave(31.3, 1), 1e-12);
}

TEST(Interpolator, RefusesACycleOutsideWhatACncDoes) {
  VirtualMachine vm(pitch::testing::PitchMachine(), 3);
  InterpolatorOptions o;
  o.cycle_s = 1.0;
  EXPECT_THROW(CncInterpolator(vm, 0, o, Wave), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::sim
