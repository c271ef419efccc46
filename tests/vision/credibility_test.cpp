// Seed-001 stop rule: more than max_rejected_in_row non-credible readings in a row stop the machine.
#include <gtest/gtest.h>

#include "trueaxis/vision/credibility.hpp"
#include "vision_test_util.hpp"

namespace trueaxis::vision {
namespace {

MarkerReading Reading(ReadingStatus s, double growth_um = 0) {
  MarkerReading r;
  r.status = s;
  r.growth_um = growth_um;
  r.reason = "test";
  return r;
}

TEST(CredibilityMonitor, StopsOnTheSixthNonCredibleReadingInARow) {
  CredibilityMonitor m(5);
  EXPECT_FALSE(m.Add(Reading(ReadingStatus::kCredible, 12.0)));
  for (int i = 0; i < 5; ++i) {
    EXPECT_FALSE(m.Add(Reading(i % 2 ? ReadingStatus::kNotCredible : ReadingStatus::kNoMarker, 99.0)));
    EXPECT_FALSE(m.stop());
  }
  EXPECT_EQ(m.rejected_in_row(), 5);
  EXPECT_DOUBLE_EQ(m.growth_um(), 12.0);  // rejected readings never change the Δz in force
  EXPECT_TRUE(m.Add(Reading(ReadingStatus::kTooFewLines)));
  EXPECT_TRUE(m.stop());
  EXPECT_NE(m.message().find("FEED HOLD"), std::string::npos);
  EXPECT_NE(m.message().find("redraw"), std::string::npos);
  EXPECT_FALSE(m.Add(Reading(ReadingStatus::kNotCredible)));  // trips once
  EXPECT_TRUE(m.stop());
  m.Reset();
  EXPECT_FALSE(m.stop());
  EXPECT_EQ(m.rejected_in_row(), 0);
}

TEST(CredibilityMonitor, ACredibleReadingResetsTheCount) {
  CredibilityMonitor m(5);
  for (int round = 0; round < 3; ++round) {
    for (int i = 0; i < 5; ++i) m.Add(Reading(ReadingStatus::kNotCredible));
    m.Add(Reading(ReadingStatus::kCredible, round));
  }
  EXPECT_FALSE(m.stop());
  EXPECT_DOUBLE_EQ(m.growth_um(), 2.0);
  EXPECT_THROW(CredibilityMonitor(0), std::invalid_argument);
}

TEST(VisionDay, AWearingMarkerTripsTheStopAndACleanDayDoesNot) {
  using namespace testing;
  VisionDayOptions clean;
  clean.hours = 4;
  clean.frame_interval_s = 1800;
  clean.program = sim::SpindleSpeedProgram::HeatingCoolingDay(4);
  const auto c = RunVisionDay(TestMarker(), TestCamera(), clean);
  EXPECT_EQ(c.stop_frame, -1);
  EXPECT_EQ(c.rejected, 0);
  EXPECT_LT(c.max_vs_marker_um, 3.0);        // the camera's part
  EXPECT_LT(c.z_error_with_rms_um, c.z_error_without_rms_um);
  VisionDayOptions worn = clean;
  worn.wear_per_hour = 0.6;  // the marker is gone within two hours
  const auto w = RunVisionDay(TestMarker(), TestCamera(), worn);
  ASSERT_GE(w.stop_frame, 0);
  EXPECT_NE(w.stop_message.find("redraw"), std::string::npos);
  // The stop comes after exactly six non-credible frames in a row.
  int in_row = 0;
  for (int i = 0; i <= w.stop_frame; ++i) in_row = w.frames[i].reading.credible() ? 0 : in_row + 1;
  EXPECT_EQ(in_row, 6);
  // Feed hold: the spindle runs down and stays stopped for the rest of the day.
  for (std::size_t i = w.stop_frame + 1; i < w.frames.size(); ++i) EXPECT_EQ(w.frames[i].rpm, 0.0) << i;
  // After the stop the Δz in force is the last credible reading.
  EXPECT_DOUBLE_EQ(w.frames[w.stop_frame].growth_in_force_um, w.frames[w.stop_frame - 6].reading.growth_um);
}

}  // namespace
}  // namespace trueaxis::vision
