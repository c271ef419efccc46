// Seed 001 in the loop: the camera's Δz reaches the virtual machine's Z through the compensator's
// limiter and reduces the Z error at the tool; the stop rule puts the machine in feed hold and
// raises the compensator's vision_stop alarm.
#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/vision/vision_loop.hpp"
#include "vision_test_util.hpp"

namespace trueaxis::vision {
namespace {
using namespace testing;

sim::MachineDescription Machine(const char* file) {
  return sim::ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/" + file);
}

VisionDayOptions ShortDay() {
  VisionDayOptions o;
  o.hours = 4;
  o.frame_interval_s = 900;
  o.program = sim::SpindleSpeedProgram::HeatingCoolingDay(4);
  return o;
}

TEST(VisionLoop, ReducesTheZErrorAtTheToolThroughTheLimiter) {
  for (const char* file : {"vmc850.toml", "vmc400_small.toml"}) {
    VisionLoopOptions lo;
    lo.compensator.shaper.max_step_um = 0.25;  // per 1 s cycle: the ramp is visible
    const auto r = RunVisionLoop(TestMarker(), TestCamera(), ShortDay(), Machine(file), lo);
    EXPECT_EQ(r.feed_hold_at_s, -1) << file;
    EXPECT_GT(r.without_max_um, 5.0) << file;  // the spindle really grows
    EXPECT_LT(r.with_rms_um, 0.6 * r.without_rms_um) << file;
    EXPECT_LT(r.with_max_um, r.without_max_um) << file;
    EXPECT_LE(r.max_output_step_um, 1.0 + 1e-9) << file;  // ≤ max(step, 1 µm quantum) per cycle: it ramps
    EXPECT_FALSE(r.alarms_seen & runtime::kAlarmVisionStop) << file;
    EXPECT_FALSE(r.alarms_seen & runtime::kAlarmCorrectionClamped) << file;
    // The correction the machine holds is the negative of the error term, i.e. +Δz in force (lagging).
    const auto& last = r.samples.back();
    EXPECT_GT(r.samples[r.samples.size() / 2].correction_um, 0.0) << file;
    EXPECT_LE(std::abs(last.z_error_with_um), std::abs(last.z_error_without_um) + 1.0) << file;
  }
}

TEST(VisionLoop, TheBoundClampsTheTermWithTheAlarm) {
  VisionLoopOptions lo;
  lo.compensator.shaper.max_correction_um = 3.0;
  const auto r = RunVisionLoop(TestMarker(), TestCamera(), ShortDay(), Machine("vmc850.toml"), lo);
  EXPECT_TRUE(r.alarms_seen & runtime::kAlarmCorrectionClamped);
  for (const auto& s : r.samples) EXPECT_LE(std::abs(s.correction_um), 3.0 + 1e-9);
}

TEST(VisionLoop, StopRulePutsTheMachineInFeedHoldAndRaisesTheAlarm) {
  VisionDayOptions o = ShortDay();
  o.wear_per_hour = 0.6;  // the marker is gone within two hours
  const auto r = RunVisionLoop(TestMarker(), TestCamera(), o, Machine("vmc850.toml"), {});
  ASSERT_GE(r.day.stop_frame, 0);
  EXPECT_EQ(r.feed_hold_at_s, r.day.frames[r.day.stop_frame].time_s);
  EXPECT_TRUE(r.alarms_seen & runtime::kAlarmVisionStop);
  EXPECT_NE(r.alarm_message.find("redraw"), std::string::npos);
  for (std::size_t i = r.day.stop_frame + 1; i < r.samples.size(); ++i) {
    EXPECT_TRUE(r.samples[i].feed_hold) << i;
    EXPECT_TRUE(r.samples[i].alarms & runtime::kAlarmVisionStop) << i;
  }
  for (int i = 0; i <= r.day.stop_frame; ++i) EXPECT_FALSE(r.samples[i].feed_hold) << i;
}

TEST(VisionLoop, RefusesAMachineWithoutTheAxis) {
  VisionLoopOptions lo;
  lo.z_axis = "W";
  EXPECT_THROW(RunVisionLoop(TestMarker(), TestCamera(), ShortDay(), Machine("vmc850.toml"), lo), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::vision
