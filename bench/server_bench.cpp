// Scale of the workshop server (issue 11): N virtual machines (sim::VirtualShop,
// one epoll thread) and the server polling them at 10 Hz (server::Shop, one epoll
// thread) in one process on this box, with the shop-wide SQLite history. Reports the
// achieved complete-cycle rate (read → step → write acknowledged) per machine, the
// read → write latency, the CPU of each loop thread, memory and history losses.
// BM_PymodbusPoller runs bench/pymodbus_poller.py (the same cycle with pymodbus) against
// the same kind of virtual shop, for comparison. Figures: bench/RESULTS.md.
//
//   ./build/bench/bench_server --benchmark_filter=Shop      (N = 10, 100, 1000, 2000)
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "../tests/server/shop_fixture.hpp"  // the tests' model and free-port virtual shop
#include "trueaxis/server/shop.hpp"
#include "trueaxis/sim_shop/virtual_shop.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace {

using namespace trueaxis;
constexpr double kPeriodS = 0.1;    // 10 Hz
constexpr double kWarmupS = 3.0;
constexpr double kMeasureS = 10.0;

double RssMb() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0;
}

std::string Dir() {
  const auto d = std::filesystem::temp_directory_path() / ("trueaxis_server_bench_" + std::to_string(getpid()));
  std::filesystem::create_directories(d);
  return d.string();
}

void BM_Shop(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const std::string dir = Dir();
  const std::string model = server::testing::WriteModel(dir + "/model.json");
  for (auto _ : state) {
    auto vshop = server::testing::StartVirtualShop(n);
    if (!vshop) {
      state.SkipWithError("cannot bind the virtual shop's ports");
      return;
    }
    server::ShopConfig config =
        server::ParseShopConfig(sim::ShopFileFor(vshop->Machines(), "127.0.0.1", model, dir + "/shop.db", kPeriodS, 0),
                                dir + "/shop.toml");
    std::filesystem::remove(dir + "/shop.db");
    store::HistoryWriterOptions ho;
    ho.queue_capacity = 1u << 18;
    store::HistoryWriter history(config.history, ho);
    const double rss0 = RssMb();
    server::Shop shop(config, &history);
    shop.Start();
    std::this_thread::sleep_for(std::chrono::duration<double>(kWarmupS));
    shop.ResetLatency();
    const auto s0 = shop.Stats();
    const auto v0 = vshop->Stats();
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(kMeasureS));
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto s1 = shop.Stats();
    const auto v1 = vshop->Stats();
    const double rss1 = RssMb();
    shop.Stop();
    history.Close();
    const auto h = history.Stats();
    const double rate = static_cast<double>(s1.complete_cycles - s0.complete_cycles) / wall;
    state.counters["machines"] = n;
    state.counters["cycles_per_s"] = rate;
    state.counters["per_machine_hz"] = rate / n;
    state.counters["p50_ms"] = s1.latency_p50_ms;
    state.counters["p99_ms"] = s1.latency_p99_ms;
    state.counters["max_ms"] = s1.latency_max_ms;
    state.counters["faults"] = static_cast<double>(s1.faults - s0.faults);
    state.counters["overruns"] = static_cast<double>(s1.overruns - s0.overruns);
    state.counters["server_cpu_pct"] = 100.0 * (s1.loop_cpu_s - s0.loop_cpu_s) / wall;
    state.counters["server_cpu_pct_per_1000"] = 100.0 * (s1.loop_cpu_s - s0.loop_cpu_s) / wall * 1000.0 / n;
    state.counters["vshop_cpu_pct"] = 100.0 * (v1.loop_cpu_s - v0.loop_cpu_s) / wall;
    state.counters["rss_mb_server_and_history"] = rss1 - rss0;
    state.counters["history_written"] = static_cast<double>(h.written);
    state.counters["history_dropped"] = static_cast<double>(h.dropped + h.failed);
    vshop->Stop();
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_Shop)->Arg(10)->Arg(100)->Arg(1000)->Arg(1500)->Arg(2000)->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);

void BM_PymodbusPoller(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  for (auto _ : state) {
    auto vshop = server::testing::StartVirtualShop(n);
    if (!vshop) {
      state.SkipWithError("cannot bind the virtual shop's ports");
      return;
    }
    const auto m = vshop->Machines().front();
    const std::string cmd = "/usr/bin/python3 " + std::string(TRUEAXIS_SOURCE_DIR) + "/bench/pymodbus_poller.py " +
                            std::to_string(m.port) + " " + std::to_string(n) + " " + std::to_string(m.axes.size()) + " " +
                            std::to_string(m.channels.size()) + " " + std::to_string(kPeriodS) + " " + std::to_string(kMeasureS) + " 2>/dev/null";
    std::string out;
    FILE* p = popen(cmd.c_str(), "r");
    char buf[4096];
    std::size_t k;
    while (p && (k = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, k);
    if (p) pclose(p);
    vshop->Stop();
    try {
      const auto j = nlohmann::json::parse(out.substr(out.find('{')));
      state.counters["machines"] = n;
      state.counters["cycles_per_s"] = j["cycles_per_s"].get<double>();
      state.counters["per_machine_hz"] = j["per_machine_hz"].get<double>();
      state.counters["p50_ms"] = j["p50_ms"].get<double>();
      state.counters["p99_ms"] = j["p99_ms"].get<double>();
      state.counters["max_ms"] = j["max_ms"].get<double>();
      state.counters["poller_cpu_pct"] = 100.0 * j["cpu_s"].get<double>() / j["elapsed_s"].get<double>();
    } catch (...) {
      state.SkipWithError(("pymodbus poller failed: " + out).c_str());
    }
  }
}
BENCHMARK(BM_PymodbusPoller)->Arg(10)->Arg(100)->Arg(200)->Arg(300)->Arg(400)->Iterations(1)->UseRealTime()->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
