// History database throughput: records per second through the writer thread
// into SQLite (WAL, batched transactions), and the producer-side cost of a push.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <unistd.h>

#include "trueaxis/store/history_writer.hpp"

namespace {
using namespace trueaxis::store;

std::string TempDb(const char* tag) {
  const auto path = std::filesystem::temp_directory_path() / (std::string("trueaxis_bench_") + tag + "_" + std::to_string(getpid()) + ".db");
  std::filesystem::remove(path);
  std::filesystem::remove(path.string() + "-wal");
  std::filesystem::remove(path.string() + "-shm");
  return path.string();
}

void Cleanup(const std::string& path) {
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
}

// End to end: push N readings (16 channels) and flush; reports records/s committed.
void BM_WriterInsertRate(benchmark::State& state) {
  const auto n = static_cast<int>(state.range(0));
  const std::string path = TempDb("rate");
  HistoryWriterOptions o;
  o.queue_capacity = 1 << 16;
  std::int64_t total = 0;
  {
    HistoryWriter writer(path, o);
    static const char* kNames[16] = {"t0", "t1", "t2", "t3", "t4", "t5", "t6", "t7",
                                     "t8", "t9", "t10", "t11", "t12", "t13", "t14", "t15"};
    double t = 0;
    for (auto _ : state) {
      for (int i = 0; i < n; ++i) {
        while (!writer.PushTemperature(t, kNames[i & 15], 20.0 + i * 1e-4, 20.0, "ok")) {
        }  // the bench wants throughput, not drops: spin when full
        if ((i & 15) == 15) t += 0.01;
      }
      writer.Flush();
      total += n;
    }
    // Each refused push while the queue was full (the loop above retries it).
    state.counters["full_retries"] = static_cast<double>(writer.Stats().dropped);
  }
  state.counters["records_per_s"] = benchmark::Counter(static_cast<double>(total), benchmark::Counter::kIsRate);
  Cleanup(path);
}
BENCHMARK(BM_WriterInsertRate)->Arg(100000)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Producer side only: what the real-time loop pays per record.
void BM_PushOnly(benchmark::State& state) {
  const std::string path = TempDb("push");
  HistoryWriterOptions o;
  o.queue_capacity = 1 << 20;
  {
    HistoryWriter writer(path, o);
    double t = 0;
    for (auto _ : state) {
      bool ok = writer.PushTemperature(t, "x_nut", 24.0, 24.0, "ok");
      benchmark::DoNotOptimize(ok);
      t += 0.01;
    }
  }
  Cleanup(path);
}
BENCHMARK(BM_PushOnly)->Iterations(200000);

}  // namespace

BENCHMARK_MAIN();
