// The fine calibration cycle: targets on the lead grid over the full travel,
// bidirectional, and the seed-002 decomposition on it without aliasing.
#include <gtest/gtest.h>

#include <cmath>

#include "pitch_test_machine.hpp"
#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/pitch/fine_cycle.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"

namespace trueaxis::pitch {
namespace {

// The targets and the range they cover: range_test.cpp (PitchRange.TheCalibrationCycleCoversTheWholeTravel).

TEST(FineCycle, TheDecompositionResolvesTheLeadHarmonicsACoarseRunCannot) {
  const auto machine = testing::PitchMachine();  // harmonics 2.0 and 0.6 µm at lead 5 mm
  FineSessionOptions so;
  so.cycle.runs = 2;
  so.cycle.per_lead = 8;  // lead/8 resolves the second harmonic too (lead/4 is its Nyquist limit)
  const auto fine = RunFineSession(machine, 0, so);
  const auto ev = analysis::Evaluate(fine.measurement);
  EXPECT_EQ(ev.targets.size(), 209u);  // 0.625 … 129.375 mm and the travel's ends (0.25, 129.75)
  analysis::DecompositionOptions d;
  d.lead_mm = 5;
  d.trend_degree = 2;
  const auto dec = analysis::Decompose(ev, d);
  ASSERT_EQ(dec.harmonics.size(), 2u);
  EXPECT_TRUE(dec.harmonics[0].resolved);
  EXPECT_TRUE(dec.harmonics[1].resolved);
  // The random part (2 µm rms, 16–120 mm waves) leaks a little into the fit.
  EXPECT_NEAR(dec.harmonics[0].amplitude_um, 2.0, 0.3);
  EXPECT_NEAR(dec.harmonics[1].amplitude_um, 0.6, 0.3);

  so.cycle.per_lead = 4;
  const auto quarter = analysis::Decompose(analysis::Evaluate(RunFineSession(machine, 0, so).measurement), d);
  EXPECT_TRUE(quarter.harmonics[0].resolved);
  EXPECT_NEAR(quarter.harmonics[0].amplitude_um, 2.0, 0.3);

  // The ISO-style 25 mm run on the same machine: the harmonics alias and are not reported.
  sim::VirtualMachine vm(machine, 1);
  sim::LaserInterferometer laser(sim::LaserOptions{}, 1);
  laser.Setup(vm, 0, 0);
  const auto coarse = analysis::Decompose(analysis::Evaluate(laser.Measure(vm, 2, {})), d);
  EXPECT_FALSE(coarse.harmonics[0].resolved);
}

TEST(FineCycle, SameSeedSameFileAndTheLaserKeepsItsZeroAcrossDays) {
  const auto machine = testing::PitchMachine();
  FineSessionOptions so;
  so.cycle.runs = 2;
  so.cycle.per_lead = 1;
  const auto a = RunFineSession(machine, 0, so), b = RunFineSession(machine, 0, so);
  ASSERT_EQ(a.measurement.points.size(), b.measurement.points.size());
  for (std::size_t i = 0; i < a.measurement.points.size(); ++i)
    EXPECT_EQ(a.measurement.points[i].deviation_um, b.measurement.points[i].deviation_um);
  so.day = 2;
  const auto later = RunFineSession(machine, 0, so);
  EXPECT_DOUBLE_EQ(later.calibration_homing.offset_um, a.homing.offset_um);  // the same day-0 zero
  EXPECT_NE(later.homing.offset_um, a.homing.offset_um);                     // re-homed
}

}  // namespace
}  // namespace trueaxis::pitch
