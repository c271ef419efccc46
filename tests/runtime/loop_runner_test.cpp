#include "trueaxis/runtime/loop_runner.hpp"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "fakes.hpp"

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

struct CountingObserver : CycleObserver {
  void OnCycle(const CycleStatus& s) override {
    ++calls;
    last_time_s = s.time_s;
  }
  long calls = 0;
  double last_time_s = 0;
};

TEST(LoopRunner, SimulatedModeAdvancesThePlantOnePeriodPerCycle) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "m");
  CountingObserver obs;
  LoopRunner runner(*comp, cnc, temps, LoopOptions{0.01}, &obs);
  double plant_time = 0;
  runner.StepSimulated(1000, [&](double dt) {
    plant_time += dt;
    cnc.axes[0].position_mm = plant_time * 10;  // 10 mm/s
    cnc.axes[0].servo_direction = 1;
  });
  EXPECT_NEAR(plant_time, 10.0, 1e-9);
  EXPECT_NEAR(runner.SimulatedTimeS(), 10.0, 1e-9);
  EXPECT_EQ(obs.calls, 1000);
  EXPECT_NEAR(obs.last_time_s, 10.0, 1e-9);
  EXPECT_EQ(cnc.writes, 1000);
  EXPECT_EQ(runner.Stats().cycles, 1000u);
  EXPECT_EQ(runner.Stats().overruns, 0u);
  runner.StepSimulated(500, nullptr);
  EXPECT_NEAR(runner.SimulatedTimeS(), 15.0, 1e-9);
}

TEST(LoopRunner, RealTimeThreadRunsUntilStopped) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  CountingObserver obs;
  LoopRunner runner(*comp, cnc, temps, LoopOptions{0.002}, &obs);
  runner.Start();
  EXPECT_TRUE(runner.Running());
  while (runner.Stats().cycles < 10) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  runner.Stop();
  EXPECT_FALSE(runner.Running());
  const auto stats = runner.Stats();
  const long writes = cnc.writes;
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(cnc.writes, writes);  // stopped means stopped
  EXPECT_EQ(static_cast<long>(stats.cycles), obs.calls);
  EXPECT_GE(stats.cycles, 10u);
  EXPECT_GT(stats.max_cycle_s, 0);
  EXPECT_FALSE(stats.BriefReport().empty());
  runner.Stop();  // idempotent
}

TEST(LoopRunner, RejectsAnAbsurdPeriod) {
  MockCnc cnc({"X"});
  MockTemperatures temps({"nut"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  EXPECT_THROW(LoopRunner(*comp, cnc, temps, LoopOptions{0}), std::invalid_argument);
  EXPECT_THROW(LoopRunner(*comp, cnc, temps, LoopOptions{100}), std::invalid_argument);
}

}  // namespace
}  // namespace trueaxis::runtime
