// PeriodicThread's call statistics: percentiles from its histogram, the longest call and which it
// was, and the calls longer than the period (what a simulated-time loop would have overrun).
#include <chrono>

#include <gtest/gtest.h>

#include "trueaxis/core/periodic_thread.hpp"

namespace trueaxis::core {
namespace {

TEST(PeriodicStats, PercentilesMaxAndLongCallsFromAccountedCalls) {
  PeriodicThread t(0.010, PeriodicThread::Clock::now(), [](double) {});
  for (int i = 0; i < 1000; ++i) {
    if (i == 0) t.Account(0.128, false);  // a slow first call (start-up)
    else if (i % 100 == 0) t.Account(0.015, false);  // 9 more beyond the 10 ms period
    else t.Account(i % 2 ? 2e-6 : 3e-6, false);
  }
  const PeriodicStats s = t.Stats();
  EXPECT_EQ(s.calls, 1000u);
  EXPECT_EQ(s.overruns, 0u);  // simulated time: none counted
  EXPECT_EQ(s.long_calls, 10u);
  EXPECT_DOUBLE_EQ(s.max_call_s, 0.128);
  EXPECT_EQ(s.max_call_number, 1u);
  // Half the calls take 2 µs, half 3 µs: the median is one of them, to the histogram's 12 %.
  EXPECT_GE(s.p50_call_s, 2e-6);
  EXPECT_LE(s.p50_call_s, 3e-6 * 1.13);
  // 1 % of 1000 calls = the 10 slow ones: the 99th percentile is still a fast call.
  EXPECT_LE(s.p99_call_s, 3e-6 * 1.13);
  t.Account(0.2, false);
  EXPECT_EQ(t.Stats().max_call_number, 1001u);
}

TEST(PeriodicStats, NoCallsNoPercentiles) {
  PeriodicThread t(0.010, PeriodicThread::Clock::now(), [](double) {});
  const PeriodicStats s = t.Stats();
  EXPECT_EQ(s.p50_call_s, 0);
  EXPECT_EQ(s.p99_call_s, 0);
}

}  // namespace
}  // namespace trueaxis::core
