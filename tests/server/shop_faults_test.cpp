// The workshop server against a virtual shop over real sockets on 127.0.0.1:
// each terminal fault (down, slow, dropping mid-request, garbage, wrong unit
// id, flapping) stays with its own machine — visible in its status — and never
// delays the healthy machines' cycles.
#include <gtest/gtest.h>

#include <cmath>

#include "shop_fixture.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {
namespace {

using namespace testing;

struct FaultCase {
  TerminalFault fault;
  double delay_s;
  const char* expected_reason;  // a piece of the status' last_fault
};

TEST(ShopFaults, EachFaultIsIsolatedAndShownOnItsOwnMachine) {
  const std::string dir = TempDir("faults");
  const std::string model = WriteModel(dir + "/model.json");
  const std::vector<FaultCase> cases = {
      {TerminalFault::kDown, 0, "connect"},
      {TerminalFault::kSilent, 0, "no answer"},
      {TerminalFault::kSlow, 0.2, "no answer"},
      {TerminalFault::kDropMidRequest, 0, "closed by the terminal"},
      {TerminalFault::kGarbage, 0, "garbage"},
      {TerminalFault::kWrongUnit, 0, "mismatched reply"},
  };
  const int healthy = 3;
  auto vshop = StartVirtualShop(healthy + static_cast<int>(cases.size()));
  ASSERT_NE(vshop, nullptr);
  for (std::size_t i = 0; i < cases.size(); ++i) vshop->SetFault(healthy + i, cases[i].fault, cases[i].delay_s);
  Shop shop(ConfigFor(*vshop, model), nullptr);
  shop.Start();
  // Wait until every faulty machine has failed at least twice (reconnect with backoff happened).
  ASSERT_TRUE(WaitFor([&] {
    for (const auto& s : shop.Snapshot())
      if ((s.name >= "vm-0003" && s.faults < 2) || (s.name < "vm-0003" && s.complete_cycles < 20)) return false;
    return true;
  }));
  const auto snap = shop.Snapshot();
  shop.Stop();
  for (int i = 0; i < healthy; ++i) {
    const MachineStatus& s = snap[i];
    EXPECT_TRUE(s.connected) << s.name;
    EXPECT_EQ(s.faults, 0u) << s.name << ": " << s.last_fault;
    EXPECT_EQ(s.overruns, 0u) << s.name;
    // Never delayed by the others: every cycle tick (but the first, which connects, the first
    // window read, which the pick-up confirms with the second before anything is written, the
    // second, whose command the next cycle's FC 23 writes, and the one in flight) completed read → write.
    EXPECT_GE(s.complete_cycles + 4, s.cycles) << s.name;
    EXPECT_GT(s.cycles, 10u) << s.name;
    for (const auto& a : s.axes) EXPECT_TRUE(a.position_mm.has_value()) << s.name << " " << a.name;
    for (const auto& c : s.channels) EXPECT_TRUE(c.temp_c.has_value()) << s.name << " " << c.name;
  }
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const MachineStatus& s = snap[healthy + i];
    EXPECT_FALSE(s.connected && s.complete_cycles > 0) << s.name;
    EXPECT_NE(s.last_fault.find(cases[i].expected_reason), std::string::npos) << s.name << ": " << s.last_fault;
    EXPECT_NE(s.alarms & 8u, 0u) << s.name << " alarms " << s.alarm_names;  // link_read
    EXPECT_EQ(s.complete_cycles, 0u) << s.name;
    // UNAVAILABLE, never a stale number.
    for (const auto& a : s.axes) {
      EXPECT_FALSE(a.position_mm.has_value()) << s.name;
      EXPECT_FALSE(a.applied_um.has_value()) << s.name;
    }
    for (const auto& c : s.channels) EXPECT_FALSE(c.temp_c.has_value()) << s.name;
  }
}

TEST(ShopFaults, AFlappingTerminalReconnectsEveryTimeAndOthersKeepTheirRate) {
  const std::string dir = TempDir("flap");
  const std::string model = WriteModel(dir + "/model.json");
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  Shop shop(ConfigFor(*vshop, model), nullptr);
  shop.Start();
  for (int flap = 0; flap < 4; ++flap) {
    const auto before = shop.Machine("vm-0001")->complete_cycles;
    ASSERT_TRUE(WaitFor([&] { return shop.Machine("vm-0001")->complete_cycles > before + 3; })) << "flap " << flap;
    vshop->SetFault(1, TerminalFault::kDown);
    const auto faults = shop.Machine("vm-0001")->faults;
    ASSERT_TRUE(WaitFor([&] { return shop.Machine("vm-0001")->faults > faults; })) << "flap " << flap;
    EXPECT_FALSE(shop.Machine("vm-0001")->axes[0].applied_um.has_value());
    vshop->SetFault(1, TerminalFault::kNone);
  }
  ASSERT_TRUE(WaitFor([&] { return shop.Machine("vm-0001")->connected; }));
  const auto s0 = *shop.Machine("vm-0000");
  const auto s1 = *shop.Machine("vm-0001");
  shop.Stop();
  EXPECT_GE(s1.connects, 5u);
  EXPECT_EQ(s0.faults, 0u);
  EXPECT_EQ(s0.overruns, 0u);
  EXPECT_GE(s0.complete_cycles + 4, s0.cycles);  // connect, pick-up read, its confirmation (written next cycle), in flight
}

// Stop the server, start a new one (fresh state): it picks the machine up where the
// CNC is — every value the terminal receives is one limiter step from the last.
TEST(ShopRestart, ANewServerContinuesFromTheAppliedCompensationWithoutAJump) {
  const std::string dir = TempDir("restart");
  const std::string model = WriteModel(dir + "/model.json");
  auto vshop = StartVirtualShop(1);
  ASSERT_NE(vshop, nullptr);
  ShopConfig config = ConfigFor(*vshop, model);
  const double step_um = config.machines[0].installation.compensator.shaper.max_step_um;
  {
    Shop first(config, nullptr);
    first.Start();
    ASSERT_TRUE(WaitFor([&] { return std::abs(vshop->AppliedUm(0)[0]) >= 10; }));
    first.Stop();
  }
  const auto held = vshop->AppliedUm(0);
  Shop second(config, nullptr);
  second.Start();
  auto last = held;
  double worst_um = 0;
  for (int i = 0; i < 200; ++i) {  // sample the CNC side while the new server takes over
    const auto now = vshop->AppliedUm(0);
    for (std::size_t a = 0; a < now.size(); ++a) worst_um = std::max(worst_um, std::abs(now[a] - last[a]));
    last = now;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const auto s = *second.Machine("vm-0000");
  second.Stop();
  EXPECT_GT(s.complete_cycles, 3u);
  EXPECT_LE(worst_um, std::max(step_um, 1.0) + 1e-9) << "the restart made the CNC jump";
}

TEST(ShopWatchdog, WhenTheServerStopsTheTerminalRampsToZeroByItself) {
  const std::string dir = TempDir("watchdog");
  const std::string model = WriteModel(dir + "/model.json");
  VirtualShopOptions o;
  o.watchdog_s = 0.2;
  o.watchdog_ramp_um_per_s = 200;
  o.tick_s = 0.01;
  auto vshop = StartVirtualShop(1, o);
  ASSERT_NE(vshop, nullptr);
  {
    Shop shop(ConfigFor(*vshop, model), nullptr);
    shop.Start();
    ASSERT_TRUE(WaitFor([&] { return std::abs(vshop->AppliedUm(0)[0]) >= 10; }));
    EXPECT_FALSE(vshop->WatchdogRamping(0));  // the server's writes refresh it
    shop.Stop();
  }
  ASSERT_TRUE(WaitFor([&] { return vshop->WatchdogRamping(0); }));
  ASSERT_TRUE(WaitFor([&] {
    for (double v : vshop->AppliedUm(0))
      if (v != 0) return false;
    return true;
  }));
}

}  // namespace
}  // namespace trueaxis::server
