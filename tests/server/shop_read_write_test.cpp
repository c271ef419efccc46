// The workshop server's client over real sockets on 127.0.0.1: one MODBUS transaction per cycle
// (FC 23: the last step's command written, the PMC window's copy read) against a terminal that
// answers it, FC 04 + FC 16 against an older terminal that answers FC 23 with exception 0x01 —
// both compensating, the terminal's CNC applying what the server computed; and the read → write
// latency kept as a histogram whose counts add up.
#include <gtest/gtest.h>

#include <cmath>

#include "shop_fixture.hpp"
#include "trueaxis/drivers/mbap.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {
namespace {

using namespace testing;
namespace mbap = drivers::mbap;

struct Counts {
  std::uint64_t read_input = 0, write_multiple = 0, read_write = 0;
};
Counts CountsOf(const VirtualShop& vshop, std::size_t machine) {
  return {vshop.Requests(machine, mbap::kReadInputRegisters), vshop.Requests(machine, mbap::kWriteMultipleRegisters),
          vshop.Requests(machine, mbap::kReadWriteMultipleRegisters)};
}

// The terminal's CNC applies what the server's status says it wrote (within one 0.1 µm count and
// one period's ramp of the rate limiter).
bool AppliedMatches(const VirtualShop& vshop, const Shop& shop, std::size_t i) {
  const auto status = shop.Snapshot()[i];
  const auto applied = vshop.AppliedUm(i);
  bool any_nonzero = false;
  for (std::size_t a = 0; a < applied.size(); ++a) {
    if (!status.axes[a].applied_um) return false;
    if (std::abs(*status.axes[a].applied_um - applied[a]) > 0.2) return false;
    any_nonzero |= std::abs(applied[a]) > 1.0;
  }
  return any_nonzero;
}

TEST(ShopReadWrite, OneTransactionPerCycleWhereTheTerminalAnswersFc23AndFc04Fc16WhereItDoesNot) {
  const std::string dir = TempDir("read_write");
  const std::string model = WriteModel(dir + "/model.json");
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  vshop->SetFault(1, TerminalFault::kNoReadWrite);  // an older terminal
  Shop shop(ConfigFor(*vshop, model), nullptr);  // (temperatures are FC 03: not among the counts below)
  ::testing::internal::CaptureStderr();
  shop.Start();
  ASSERT_TRUE(WaitFor([&] {
    const auto snap = shop.Snapshot();
    return snap[0].complete_cycles >= 10 && snap[1].complete_cycles >= 10;
  }));
  // Steady state: count the requests of at least 10 further cycles of each machine.
  const Counts fc23_before = CountsOf(*vshop, 0), old_before = CountsOf(*vshop, 1);
  const auto snap_before = shop.Snapshot();
  ASSERT_TRUE(WaitFor([&] {
    const auto snap = shop.Snapshot();
    return snap[0].complete_cycles >= snap_before[0].complete_cycles + 10 &&
           snap[1].complete_cycles >= snap_before[1].complete_cycles + 10;
  }));
  const Counts fc23_after = CountsOf(*vshop, 0), old_after = CountsOf(*vshop, 1);
  ASSERT_TRUE(WaitFor([&] { return AppliedMatches(*vshop, shop, 0) && AppliedMatches(*vshop, shop, 1); }));
  const auto snap = shop.Snapshot();
  shop.Stop();
  const std::string log = ::testing::internal::GetCapturedStderr();

  // The older terminal's two transactions a cycle are said once, naming it; the other is not named.
  const std::string said = "machine '" + snap[1].name + "': the terminal refuses FC 23";
  EXPECT_NE(log.find(said), std::string::npos) << log;
  EXPECT_EQ(log.find(said), log.rfind(said)) << log;
  EXPECT_EQ(log.find("machine '" + snap[0].name + "': the terminal refuses"), std::string::npos) << log;

  // The terminal that answers FC 23: every cycle one FC 23, no FC 04 or FC 16.
  EXPECT_GE(fc23_after.read_write - fc23_before.read_write, 10u);
  EXPECT_EQ(fc23_after.read_input, fc23_before.read_input);
  EXPECT_EQ(fc23_after.write_multiple, 0u);
  // The older terminal: asked FC 23 once on its connection, then FC 04 + FC 16 every cycle.
  EXPECT_EQ(old_after.read_write, 1u);
  EXPECT_GE(old_after.read_input - old_before.read_input, 10u);
  EXPECT_GE(old_after.write_multiple - old_before.write_multiple, 10u);
  for (const auto& s : snap) {
    EXPECT_TRUE(s.connected) << s.name;
    EXPECT_EQ(s.faults, 0u) << s.name << ": " << s.last_fault;
    EXPECT_EQ(s.overruns, 0u) << s.name;
    EXPECT_EQ(s.alarms, 0u) << s.name << ": " << s.alarm_names;  // the refused FC 23 is no link fault
  }
}

TEST(ShopReadWrite, AnFc23WhoseWriteTheTerminalRefusesRaisesLinkWriteAndTheWindowIsStillReadEachCycle) {
  const std::string dir = TempDir("read_write_refused");
  const std::string model = WriteModel(dir + "/model.json");  // tens of µm of correction
  VirtualShopOptions o;
  o.max_compensation_um = 5;  // the terminal refuses (0x03) any vector beyond ±5 µm
  auto vshop = StartVirtualShop(1, o);
  ASSERT_NE(vshop, nullptr);
  Shop shop(ConfigFor(*vshop, model), nullptr);
  shop.Start();
  // The refused write is shown (alarm link_write) …
  ASSERT_TRUE(WaitFor([&] { return (shop.Snapshot()[0].alarms & runtime::kAlarmLinkWrite) != 0; }));
  const Counts before = CountsOf(*vshop, 0);
  const std::uint64_t refused_before = vshop->Stats().exceptions;
  const auto cycles_before = shop.Snapshot()[0].cycles;
  ASSERT_TRUE(WaitFor([&] { return shop.Snapshot()[0].cycles >= cycles_before + 20; }));
  const Counts after = CountsOf(*vshop, 0);
  const std::uint64_t refused = vshop->Stats().exceptions - refused_before;
  const auto s = shop.Snapshot()[0];
  shop.Stop();
  // … each refused FC 23 read nothing, so the window is read alone (FC 04) in the same cycle: the
  // machine stays connected and its positions known while the terminal keeps refusing.
  EXPECT_GE(refused, 3u);
  // (the span may cut one cycle between its refused FC 23 and its FC 04; a cycle with nothing to
  // write reads by FC 04 too)
  EXPECT_GE(after.read_input - before.read_input + 1, refused);
  EXPECT_GE(after.read_write - before.read_write, refused);
  EXPECT_TRUE(s.connected);
  EXPECT_EQ(s.faults, 0u) << s.last_fault;
  for (const auto& a : s.axes) EXPECT_TRUE(a.position_mm.has_value()) << a.name;
  for (double applied_um : vshop->AppliedUm(0)) EXPECT_LE(std::abs(applied_um), 5.0);  // never beyond its bound
}

TEST(ShopReadWrite, TheLatencyHistogramCountsEveryCompleteCycleAndResets) {
  const std::string dir = TempDir("latency");
  const std::string model = WriteModel(dir + "/model.json");
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  Shop shop(ConfigFor(*vshop, model), nullptr);
  shop.Start();
  ASSERT_TRUE(WaitFor([&] { return shop.Stats().complete_cycles >= 20; }));
  shop.Stop();  // nothing moves while the figures are compared
  const ShopStats s = shop.Stats();
  std::uint64_t counted = 0;
  double previous_edge = 0;
  for (const auto& [edge_ms, count] : s.latency_histogram) {
    EXPECT_GT(edge_ms, previous_edge);  // ascending buckets, empty ones left out
    EXPECT_GT(count, 0u);
    previous_edge = edge_ms;
    counted += count;
  }
  EXPECT_EQ(counted, s.latency_samples);
  EXPECT_EQ(s.latency_samples, s.complete_cycles);
  EXPECT_GT(s.latency_p50_ms, 0.0);
  EXPECT_LE(s.latency_p50_ms, s.latency_p99_ms);
  EXPECT_LE(s.latency_p99_ms, s.latency_max_ms);
  EXPECT_GE(s.latency_max_ms, s.latency_histogram.back().first / 1.07);  // the max lies in the last bucket
  shop.ResetLatency();
  const ShopStats r = shop.Stats();
  EXPECT_EQ(r.latency_samples, 0u);
  EXPECT_TRUE(r.latency_histogram.empty());
  EXPECT_EQ(r.complete_cycles, s.complete_cycles);  // the counters stay
}

}  // namespace
}  // namespace trueaxis::server
