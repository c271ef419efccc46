// core::PeriodicWorker, the thread behind the low-rate publishers (the MQTT relay, the web
// front end's shop sampler): a tick at once, ticks every period, and Stop() wakes it at once.
#include "trueaxis/core/periodic_worker.hpp"

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace trueaxis::core {
namespace {

TEST(PeriodicWorker, TicksAtOnceThenEveryPeriodAndStopsWithoutWaitingOutAPeriod) {
  std::atomic<int> ticks{0};
  PeriodicWorker w;
  w.Start(0.01, [&] { ++ticks; });
  while (ticks.load() < 5) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  w.Stop();
  const int after_stop = ticks.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(ticks.load(), after_stop) << "ticked after Stop()";
  EXPECT_FALSE(w.running());

  // a long period: the first tick comes at once, Stop() returns without the hour
  std::atomic<int> slow{0};
  w.Start(3600, [&] { ++slow; });
  while (slow.load() < 1) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const auto t0 = std::chrono::steady_clock::now();
  w.Stop();
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(60));  // not the period: the worker was woken
  EXPECT_EQ(slow.load(), 1);
}

}  // namespace
}  // namespace trueaxis::core
