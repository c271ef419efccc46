// core::PeriodicThread, the one periodic loop (the compensator's loop and I/O workers, the
// terminal's machine exchange and temperature poller, the shop sampler, the MQTT relay, the
// MTConnect agent): a call at once, calls on the period grid, overruns counted and skipped,
// Wake() for a call out of turn, and Stop() that wakes it at once. No assertion on how long
// anything takes: counts and order only.
#include "trueaxis/core/periodic_thread.hpp"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace trueaxis::core {
namespace {

// Waits (no time limit of its own: ctest's timeout is the limit) until `done` holds.
template <typename Pred>
void WaitUntil(Pred done) {
  while (!done()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

TEST(PeriodicThread, CallsAtOnceThenEveryPeriodAndNotAfterStop) {
  std::atomic<int> calls{0};
  PeriodicThread t;
  t.Start(0.01, [&](double) { ++calls; });
  WaitUntil([&] { return calls.load() >= 5; });
  t.Stop();
  EXPECT_FALSE(t.Running());
  const int after_stop = calls.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(calls.load(), after_stop) << "called after Stop()";
  EXPECT_EQ(t.Stats().calls, static_cast<std::uint64_t>(after_stop));
}

// An hour's period: the first call comes at once, and Stop() returns — had it waited out the
// period the test would hang (and ctest's timeout would fail it), not pass slowly.
TEST(PeriodicThread, StopWakesTheThreadInsteadOfWaitingOutThePeriod) {
  std::atomic<int> calls{0};
  PeriodicThread t;
  t.Start(3600, [&](double) { ++calls; });
  WaitUntil([&] { return calls.load() >= 1; });
  t.Stop();
  EXPECT_EQ(calls.load(), 1);
  EXPECT_EQ(t.Stats().overruns, 0u);
}

// Wake() asks for one call now, on an hour's period: without it there would be no second call.
TEST(PeriodicThread, WakeCallsOnceOutOfTurn) {
  std::mutex mu;
  std::condition_variable cv;
  int calls = 0;
  PeriodicThread t;
  t.Start(3600, [&](double) {
    std::lock_guard lock(mu);
    ++calls;
    cv.notify_all();
  });
  {
    std::unique_lock lock(mu);
    cv.wait(lock, [&] { return calls == 1; });
  }
  t.Wake();
  {
    std::unique_lock lock(mu);
    cv.wait(lock, [&] { return calls == 2; });
  }
  t.Stop();
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(t.Stats().calls, 2u);
  EXPECT_EQ(t.Stats().overruns, 0u);
}

// Each call outlasts its deadline: every call is an overrun, and the missed deadlines are skipped
// (not caught up in a burst), so the calls do not pile up: each starts after the last one ended.
TEST(PeriodicThread, CallsLongerThanThePeriodAreCountedOverrunsAndSkipped) {
  std::atomic<int> calls{0};
  std::vector<std::pair<double, double>> spans;  // start, end of each call (seconds from the epoch)
  std::mutex mu;
  const auto epoch = PeriodicThread::Clock::now();
  PeriodicThread t(0.001, epoch, [&](double now_s) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // 5 periods
    const double end_s = std::chrono::duration<double>(PeriodicThread::Clock::now() - epoch).count();
    std::lock_guard lock(mu);
    spans.emplace_back(now_s, end_s);
    ++calls;
  });
  t.Start();
  WaitUntil([&] { return calls.load() >= 6; });
  t.Stop();
  const PeriodicStats s = t.Stats();
  EXPECT_EQ(s.calls, static_cast<std::uint64_t>(calls.load()));
  EXPECT_EQ(s.overruns, s.calls);  // sleep_for sleeps at least 5 ms: every call ends after its deadline
  EXPECT_EQ(s.long_calls, s.calls);
  std::lock_guard lock(mu);
  for (std::size_t i = 1; i < spans.size(); ++i) {
    EXPECT_GE(spans[i].first, spans[i - 1].second) << "call " << i << " started before the previous one ended";
    // the next deadline on the grid after the overrun: less than one period after the end
    // is not asserted (a loaded computer may wake late); the order is
  }
}

// A restart with another period and body: the old body is not called again.
TEST(PeriodicThread, StartWithANewBodyReplacesTheRunningOne) {
  std::atomic<int> first{0}, second{0};
  PeriodicThread t;
  t.Start(0.001, [&](double) { ++first; });
  WaitUntil([&] { return first.load() >= 1; });
  t.Start(0.001, [&](double) { ++second; });
  const int first_at_restart = first.load();
  WaitUntil([&] { return second.load() >= 3; });
  t.Stop();
  EXPECT_EQ(first.load(), first_at_restart);
}

}  // namespace
}  // namespace trueaxis::core
