// A long gap with no samples at all (the machine was switched off overnight) restarts a channel's
// filter: the first reading after it is taken as it is, not rejected as a spike against yesterday's
// median window (the demo's "another day" compensated with the previous day's warm nut, 19 µm off).
#include <gtest/gtest.h>

#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::signal {
namespace {

double FilteredAfterGap(double gap_s) {
  TemperatureMonitor monitor({"x_nut"});
  double t = 0;
  for (int i = 0; i < 600; ++i, t += 0.1) monitor.Update(t, std::vector<hw::RawTemperature>{{30.0, false}});
  t += gap_s;
  monitor.Update(t, std::vector<hw::RawTemperature>{{21.0, false}});
  return monitor.reading(0).filtered_c;
}

TEST(GapRestart, TheFirstReadingAfterALongGapIsTakenAsItIs) {
  EXPECT_NEAR(FilteredAfterGap(86400.0), 21.0, 1e-9);  // a day off
  EXPECT_NEAR(FilteredAfterGap(MonitorOptions{}.faults.restart_after_gap_s + 1), 21.0, 1e-9);
}

TEST(GapRestart, ARegularSampleIsStillFilteredAgainstItsWindow) {
  EXPECT_GT(FilteredAfterGap(0.0), 25.0);  // a 9 °C jump between two 10 Hz samples: a spike, rejected
}

}  // namespace
}  // namespace trueaxis::signal
