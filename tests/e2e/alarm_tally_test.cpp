// AlarmTally: the demo report's alarm summary from the alarm word of each cycle.
#include "trueaxis/demo/alarm_tally.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/runtime/cycle_step.hpp"

namespace trueaxis::demo {
namespace {

TEST(AlarmTally, CountsEpisodesTheirTotalDurationAndFirstAndLastTimes) {
  using namespace runtime;
  AlarmTally t;
  t.Update(0, 0);
  t.Update(kAlarmModelExtrapolated, 100);                         // raised
  t.Update(kAlarmModelExtrapolated | kAlarmSensorHeld, 130);     // a second alarm joins
  t.Update(kAlarmModelExtrapolated, 160);                         // sensor_held cleared after 30 s
  t.Update(0, 200);                                               // model_extrapolated: 100 s
  t.Update(kAlarmModelExtrapolated, 500);                         // again, still active at the pause
  t.Pause(520);                                                   // the machine switched off
  t.Update(kAlarmModelExtrapolated, 10'000);                      // the next day: raised anew
  const auto rows = t.Rows(10'050);                               // still active at the end
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].alarm, "sensor_held");  // bit order
  EXPECT_EQ(rows[0].times, 1u);
  EXPECT_DOUBLE_EQ(rows[0].total_s, 30);
  EXPECT_DOUBLE_EQ(rows[0].first_raised_s, 130);
  EXPECT_DOUBLE_EQ(rows[0].last_cleared_s, 160);
  EXPECT_EQ(rows[1].alarm, "model_extrapolated");
  EXPECT_EQ(rows[1].times, 3u);
  EXPECT_DOUBLE_EQ(rows[1].total_s, 100 + 20 + 50);  // the night off is not counted
  EXPECT_DOUBLE_EQ(rows[1].first_raised_s, 100);
  EXPECT_DOUBLE_EQ(rows[1].last_raised_s, 10'000);
  EXPECT_TRUE(std::isnan(rows[1].last_cleared_s));    // still active at the end
}

TEST(AlarmTally, NoAlarmNoRows) {
  AlarmTally t;
  t.Update(0, 5);
  EXPECT_TRUE(t.Rows(10).empty());
}

}  // namespace
}  // namespace trueaxis::demo
