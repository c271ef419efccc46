// Proves the compensation cycle allocates nothing: global operator new and
// delete are replaced (for this whole test program) by versions that count
// while `g_counting` is set. Faults, link losses, model swaps and enable
// toggles all happen inside the counted window.
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <new>
#include <thread>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
std::atomic<long> g_frees{0};

void* CountedAlloc(std::size_t n, std::size_t align = 0) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (n == 0) n = 1;
  void* p = align > alignof(std::max_align_t) ? std::aligned_alloc(align, (n + align - 1) / align * align) : std::malloc(n);
  if (!p) throw std::bad_alloc();
  return p;
}
void CountedFree(void* p) {
  if (p && g_counting.load(std::memory_order_relaxed)) g_frees.fetch_add(1, std::memory_order_relaxed);
  std::free(p);
}
}  // namespace

void* operator new(std::size_t n) { return CountedAlloc(n); }
void* operator new[](std::size_t n) { return CountedAlloc(n); }
void* operator new(std::size_t n, std::align_val_t a) { return CountedAlloc(n, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return CountedAlloc(n, static_cast<std::size_t>(a)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try { return CountedAlloc(n); } catch (...) { return nullptr; }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try { return CountedAlloc(n); } catch (...) { return nullptr; }
}
void operator delete(void* p) noexcept { CountedFree(p); }
void operator delete[](void* p) noexcept { CountedFree(p); }
void operator delete(void* p, std::size_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::size_t) noexcept { CountedFree(p); }
void operator delete(void* p, std::align_val_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::align_val_t) noexcept { CountedFree(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { CountedFree(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { CountedFree(p); }

namespace trueaxis::runtime {
namespace {
using testing::MockCnc;
using testing::MockTemperatures;
using testing::TestModel;

TEST(NoAllocation, CounterSeesAllocations) {  // the instrument works
  g_allocations = 0;
  g_counting = true;
  auto* v = new std::vector<int>(100);
  g_counting = false;
  delete v;
  EXPECT_GE(g_allocations.load(), 2);
}

TEST(NoAllocation, ManyCyclesWithFaultsSwapsAndTogglesAllocateNothing) {
  MockCnc cnc({"X", "Y", "Z"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 20.0);
  CompensatorOptions o;
  o.shaper.max_step_um = 0.5;
  o.sensor.hold_last_good_s = 0.5;
  auto comp = Compensator::ForHardware(o, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X", "Y", "Z"}), "a");
  double t = 0;
  for (int c = 0; c < 100; ++c) comp->RunCycle(cnc, temps, t += 0.01);  // warm-up
  comp->PublishModel(TestModel(3.0, {"X", "Y"}), "b");  // picked up inside the counted window

  g_allocations = 0;
  g_frees = 0;
  g_counting = true;
  for (int c = 0; c < 100000; ++c) {
    cnc.axes[0].position_mm = (c % 5000) * 0.1;
    cnc.axes[0].servo_direction = (c / 5000) % 2 ? -1 : 1;
    cnc.axes[0].moving = (c % 5000) != 0;
    cnc.axes[1].position_mm = 200 + (c % 300);
    temps.values[1].temp_c = 20 + (c % 10000) * 1e-3;
    temps.values[1].hardware_fault = (c % 20000) > 19000;  // held, then lost
    temps.values[0].temp_c = (c % 7777) == 0 ? std::nan("") : 21.0;
    cnc.fail_read = (c % 9000) > 8800;
    cnc.fail_write = (c % 1000) == 3;
    cnc.machine.coolant = (c / 3000) % 2 ? CoolantState::kFlood : CoolantState::kOff;
    if (c % 4000 == 0) comp->SetEnabled(c % 8000 != 0);
    if (c % 2500 == 0) comp->SetExtraErrorUm(2, (c % 5000) ? 12.0 : std::nan(""), t + 10.0);  // vision Δz on Z
    comp->RunCycle(cnc, temps, t += 0.01);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_EQ(g_frees.load(), 0);
  EXPECT_NE(comp->LastStatus().model_id, 1u);  // the swap did happen
}

TEST(NoAllocation, SignalProcessingInFrontOfTheCompensatorAllocatesNothing) {
  MockCnc cnc({"X"});
  MockTemperatures raw({"ambient", "nut", "bearing"}, 20.0);
  double now = 0;
  signal::MonitoredTemperatureSource temps(raw, signal::MonitorOptions{}, [&] { return now; });
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  comp->PublishModel(TestModel(1.0, {"X"}), "a");
  for (int c = 0; c < 100; ++c) comp->RunCycle(cnc, temps, now += 0.01);
  g_allocations = 0;
  g_counting = true;
  for (int c = 0; c < 50000; ++c) {
    raw.values[1].temp_c = 20 + (c % 5000) * 1e-3 + ((c % 997) == 0 ? 9 : 0);
    raw.values[2].hardware_fault = (c % 10000) > 9000;
    raw.fail = (c % 7000) == 1;
    comp->RunCycle(cnc, temps, now += 0.01);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(NoAllocation, RealTimeLoopThreadAllocatesNothingOnceRunning) {
  MockCnc cnc({"X", "Y"});
  MockTemperatures temps({"ambient", "nut", "bearing"}, 20.0);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  comp->PublishModel(TestModel(), "a");
  CycleRecorder recorder(4096, 1);  // the logging observer runs on the loop thread too
  LoopRunner runner(*comp, cnc, temps, LoopOptions{0.001}, &recorder);
  runner.Start();
  while (runner.Stats().cycles < 5) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  const auto before = runner.Stats().cycles;
  g_allocations = 0;
  g_counting = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // this thread does nothing meanwhile
  g_counting = false;
  const auto after = runner.Stats().cycles;
  runner.Stop();
  EXPECT_GT(after, before);
  EXPECT_EQ(g_allocations.load(), 0);
  CycleRecord r;
  EXPECT_TRUE(recorder.Pop(r));
}

}  // namespace
}  // namespace trueaxis::runtime
