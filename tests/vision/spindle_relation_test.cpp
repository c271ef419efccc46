// The marker is not the whole spindle: the seed's reading Czb·(K − 1) misses more the faster the
// spindle turns; the relation calibrated from one reference day removes most of it on other
// speed programs and says when a speed lies beyond its calibration.
#include "trueaxis/vision/spindle_relation.hpp"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

#include "trueaxis/sim/spindle.hpp"

namespace trueaxis::vision {
namespace {

// One sample every 5 min of a 10 h day: the perfect marker reading, the speed and the real growth.
std::vector<SpindleRelationSample> Day(const sim::SpindleSpeedProgram& program) {
  sim::SpindleDescription d;
  sim::VirtualSpindle s(d, program, d.standard_temp_c);
  std::vector<SpindleRelationSample> out;
  for (double t = 0; t <= 10 * 3600; t += 300) {
    s.AdvanceTo(t);
    out.push_back({t, d.length_mm * 1000 * s.MarkerStrain(), s.Rpm(), s.GrowthUm()});
  }
  return out;
}

sim::SpindleSpeedProgram Constant(double rpm) { return sim::SpindleSpeedProgram({{0, 0}, {1200, rpm}, {6 * 3600.0, 0}}); }
sim::SpindleSpeedProgram ScaledDay(double f) {
  return sim::SpindleSpeedProgram({{0, 0}, {1440, 10000 * f}, {10800, 6000 * f}, {15120, 8000 * f}, {21600, 0}});
}

double SeedRms(const std::vector<SpindleRelationSample>& day) {
  double ss = 0;
  for (const auto& p : day) ss += std::pow(p.marker_um - p.reference_um, 2);
  return std::sqrt(ss / day.size());
}

double RelationRms(const SpindleRelation& r, const std::vector<SpindleRelationSample>& day, bool* beyond = nullptr) {
  SpindleRelationPredictor p(r);
  double ss = 0;
  for (const auto& s : day) ss += std::pow(p.Push(s.time_s, s.marker_um, s.rpm) - s.reference_um, 2);
  if (beyond) *beyond = p.beyond_calibration();
  return std::sqrt(ss / day.size());
}

TEST(SpindleRelation, TheSeedsReadingMissesMoreTheFasterTheSpindleTurns) {
  const double at6 = SeedRms(Day(Constant(6000))), at10 = SeedRms(Day(Constant(10000))), at15 = SeedRms(Day(Constant(15000)));
  EXPECT_GT(at10, 2 * at6);
  EXPECT_GT(at15, 2 * at10);
  EXPECT_GT(at15, 10.0);  // µm: far above the heating/cooling day's 3.9 µm
}

TEST(SpindleRelation, CalibratedOnOneDayItFollowsOtherSpeedPrograms) {
  const SpindleRelation r = FitSpindleRelation(Day(sim::SpindleSpeedProgram::HeatingCoolingDay(10)));
  EXPECT_DOUBLE_EQ(r.calibrated_rpm_max, 10000);
  EXPECT_LT(r.calibration_rms_um, 1.0);
  // Within the calibrated speeds: under 1 µm RMS, and at most half the seed's reading.
  for (double rpm : {6000.0, 10000.0}) {
    const auto day = Day(Constant(rpm));
    bool beyond = true;
    EXPECT_LT(RelationRms(r, day, &beyond), 1.0) << rpm;
    EXPECT_LT(RelationRms(r, day), 0.5 * SeedRms(day)) << rpm;
    EXPECT_FALSE(beyond) << rpm;
  }
  // Beyond them it still helps, and it says it extrapolates.
  for (const auto& program : {Constant(15000), ScaledDay(1.5)}) {
    const auto day = Day(program);
    bool beyond = false;
    EXPECT_LT(RelationRms(r, day, &beyond), 0.35 * SeedRms(day));
    EXPECT_TRUE(beyond);
  }
  EXPECT_TRUE(SpindleRelationSpeedWarning(r, 10100).empty());
  const std::string w = SpindleRelationSpeedWarning(r, 15000);
  EXPECT_NE(w.find("15000 rpm"), std::string::npos);
  EXPECT_NE(w.find("10000 rpm"), std::string::npos);
}

TEST(SpindleRelation, ARunThatNeverChangesSpeedOrIsTooShortIsRefused) {
  auto day = Day(Constant(8000));
  for (auto& s : day) s.rpm = 8000;
  EXPECT_THROW(FitSpindleRelation(day), std::invalid_argument);
  EXPECT_THROW(FitSpindleRelation(std::vector<SpindleRelationSample>(day.begin(), day.begin() + 5)), std::invalid_argument);
  auto back = Day(Constant(8000));
  back[7].time_s = back[6].time_s;
  EXPECT_THROW(FitSpindleRelation(back), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::vision
