#include "trueaxis/runtime/cycle_recorder.hpp"

#include <thread>

#include <gtest/gtest.h>

#include "fakes.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

TEST(SpscRing, FifoAndFullness) {
  SpscRing<int> ring(3);  // rounded up to 4
  EXPECT_EQ(ring.Capacity(), 4u);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.TryPush(i));
  EXPECT_FALSE(ring.TryPush(99));
  int v = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(ring.TryPop(v));
    EXPECT_EQ(v, i);
  }
  EXPECT_FALSE(ring.TryPop(v));
}

TEST(SpscRing, TwoThreadsDeliverEverythingInOrder) {
  SpscRing<long> ring(64);
  constexpr long kN = 200000;
  std::thread producer([&] {
    for (long i = 0; i < kN; ++i)
      while (!ring.TryPush(i)) std::this_thread::yield();
  });
  long expected = 0, v = 0;
  while (expected < kN) {
    if (ring.TryPop(v)) {
      ASSERT_EQ(v, expected);
      ++expected;
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();
}

TEST(CycleRecorder, DecimatesButKeepsEveryAlarmEdge) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  CycleRecorder rec(1024, 100);
  LoopRunner runner(*comp, cnc, temps, LoopOptions{0.01}, &rec);
  runner.StepSimulated(500, nullptr);
  cnc.fail_read = true;  // raise at cycle 501
  runner.StepSimulated(7, nullptr);
  cnc.fail_read = false;  // cleared after 3 good reads (cycle 510)
  runner.StepSimulated(490, nullptr);
  std::vector<CycleRecord> got;
  CycleRecord r;
  while (rec.Pop(r)) got.push_back(r);
  std::vector<std::uint64_t> cycles;
  for (const auto& g : got) cycles.push_back(g.cycle);
  // first cycle, every 100th, the raise (501) and the clear (510)
  const std::vector<std::uint64_t> want = {1, 100, 200, 300, 400, 500, 501, 510, 600, 700, 800, 900};
  EXPECT_EQ(cycles, want);
  EXPECT_TRUE(got[6].alarms & kAlarmLinkRead);
  EXPECT_FALSE(got[7].alarms & kAlarmLinkRead);
  EXPECT_EQ(got[0].axis_count, 1);
  EXPECT_EQ(got[0].channel_count, 3);
  EXPECT_DOUBLE_EQ(got[0].temp_c[1], 20.0);
  EXPECT_EQ(rec.Dropped(), 0u);
}

TEST(CycleRecorder, CountsDropsWhenTheConsumerFallsBehind) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"nut"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  CycleRecorder rec(16, 1);
  LoopRunner runner(*comp, cnc, temps, LoopOptions{0.01}, &rec);
  runner.StepSimulated(100, nullptr);
  EXPECT_EQ(rec.Dropped(), 84u);
}

}  // namespace
}  // namespace trueaxis::runtime
