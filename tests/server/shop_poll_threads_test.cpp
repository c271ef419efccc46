// The machines split over several polling threads ([server] poll_threads):
// every machine cycles, its history rows arrive, and the shop's counters and
// latency histogram count every machine of every thread.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "shop_fixture.hpp"
#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::server {
namespace {

using namespace trueaxis::server::testing;

TEST(ShopPollThreads, TwoThreadsCycleEveryMachineRecordItsHistoryAndCountItInTheStats) {
  const std::string dir = TempDir("poll_threads");
  const int n = 6;
  auto vshop = StartVirtualShop(n);
  ASSERT_NE(vshop, nullptr);
  ShopConfig config = ConfigFor(*vshop, WriteModel(dir + "/model.json"));
  config.poll_threads = 2;
  config.history = dir + "/shop.db";
  config.record_interval_s = 0.1;
  auto writer = std::make_unique<store::HistoryWriter>(config.history);
  Shop shop(config, writer.get());
  shop.Start();
  ASSERT_TRUE(WaitUntilEveryMachineReads(shop));
  ASSERT_TRUE(WaitFor([&] {
    for (const auto& m : shop.Snapshot())
      if (m.complete_cycles < 10) return false;
    return true;
  }));
  const ShopStats running = shop.Stats();
  EXPECT_EQ(running.poll_threads, 2);
  EXPECT_GT(running.loop_cpu_s, 0);  // the threads' CPU time, while they run
  shop.Stop();
  writer->Close();

  const ShopStats st = shop.Stats();
  std::uint64_t cycles = 0, complete = 0, faults = 0, overruns = 0;
  for (const auto& m : shop.Snapshot()) {
    EXPECT_TRUE(m.connected) << m.name << ": " << m.last_fault;
    EXPECT_GE(m.complete_cycles, 10u) << m.name;
    cycles += m.cycles;
    complete += m.complete_cycles;
    faults += m.faults;
    overruns += m.overruns;
  }
  // A machine's status is published within its cycle, its counters may be one ahead of it.
  EXPECT_GE(st.cycles, cycles);
  EXPECT_LE(st.cycles, cycles + n);
  EXPECT_GE(st.complete_cycles, complete);
  EXPECT_LE(st.complete_cycles, complete + n);
  EXPECT_EQ(st.faults, faults);
  EXPECT_GE(st.overruns, overruns);
  EXPECT_LE(st.overruns, overruns + n);
  // Both threads' histograms merged: one latency sample per complete cycle of every machine.
  EXPECT_EQ(st.latency_samples, st.complete_cycles);
  std::uint64_t in_buckets = 0;
  for (const auto& [edge_ms, count] : st.latency_histogram) in_buckets += count;
  EXPECT_EQ(in_buckets, st.complete_cycles);
  EXPECT_GT(st.latency_p99_ms, 0);
  shop.ResetLatency();
  EXPECT_EQ(shop.Stats().latency_samples, 0u);  // every thread's histogram cleared

  // The history rows of the machines of both threads (machine i is on thread i mod 2).
  store::HistoryDb db(config.history, store::HistoryDb::Mode::kReadOnly);
  for (const auto& m : shop.MachineNames()) {
    EXPECT_FALSE(db.QueryCompensation({}, {m + "/X"}).empty()) << m;
    EXPECT_FALSE(db.QueryTemperatures({}, {m + "/ambient"}).empty()) << m;
  }
  EXPECT_EQ(db.QueryModelChanges({}).size(), static_cast<std::size_t>(n));  // one start each
}

TEST(ShopPollThreads, NoMoreThreadsThanMachinesAndOutOfRangeIsRefused) {
  const std::string dir = TempDir("poll_threads_range");
  auto vshop = StartVirtualShop(1);
  ASSERT_NE(vshop, nullptr);
  ShopConfig config = ConfigFor(*vshop, WriteModel(dir + "/model.json"));
  config.poll_threads = 4;
  EXPECT_EQ(Shop(config, nullptr).Stats().poll_threads, 1);
  for (int bad : {0, -1, kMaxPollThreads + 1}) {
    config.poll_threads = bad;
    try {
      Shop shop(config, nullptr);
      FAIL() << "poll_threads " << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "server.poll_threads") << e.what();
      EXPECT_EQ(e.source(), config.source) << e.what();
    }
  }
}

// The command line: the shop file's value and --poll-threads, each refused out of range (exit 2)
// naming where it came from, before anything is polled.
TEST(ShopPollThreads, TheServerCommandRefusesOutOfRangeThreadCountsNamingTheSetting) {
  const std::string dir = TempDir("poll_threads_cli");
  const std::string model = WriteModel(dir + "/model.json");
  const std::string shop = dir + "/shop.toml";
  auto write = [&](int k) {
    std::ofstream(shop) << "[server]\npoll_threads = " << k << "\n\n[[machine]]\nname = \"m1\"\nport = 1\naxes = [\"X\", \"Y\", \"Z\"]\n"
                        << "model = \"" << model << "\"\n";
  };
  write(kMaxPollThreads + 1);
  auto r = trueaxis::testing::RunCli("server --config " + shop + " --duration-s 0.1 --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(shop + ":2: field 'server.poll_threads'"), std::string::npos) << r.output;
  write(1);
  r = trueaxis::testing::RunCli("server --config " + shop + " --duration-s 0.1 --quiet --poll-threads 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--poll-threads': 0 is out of range"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace trueaxis::server
