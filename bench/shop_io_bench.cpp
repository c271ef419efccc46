// The workshop server's outward I/O (issue 11): history batches into a real
// PostgreSQL 15 (started here as in the tests: temporary directory, unix
// socket, as `nobody` under root) beside the SQLite file, and MQTT publishes
// with QoS 1 to a real mosquitto on 127.0.0.1. Figures: bench/results/shop_io.md.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "../tests/live/mosquitto_broker.hpp"
#include "../tests/store_postgres/postgres_server.hpp"
#include "trueaxis/live/mqtt_publisher.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store_postgres/postgres_history_sink.hpp"

namespace {

using namespace trueaxis;

// One batch as a 1,000-machine shop's cycle would give it: temperatures and compensations of many names.
std::vector<store::HistoryRecord> Batch(std::size_t n, double t0) {
  std::vector<store::HistoryRecord> b;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string name = "m" + std::to_string(i % 250) + "_ch" + std::to_string(i % 7);
    if (i % 4 == 3)
      b.push_back(store::HistoryRecord::Compensation(t0 + 0.1 * i, "X", 100.0 + i, -3.0 + 0.001 * i, "active"));
    else
      b.push_back(store::HistoryRecord::Temperature(t0 + 0.1 * i, name, 20.0 + 0.001 * i, 20.0, "ok"));
  }
  return b;
}

// Batches of range(0) records into `sink`, one transaction each.
void InsertBatches(benchmark::State& state, store::HistorySink& sink) {
  const auto n = static_cast<std::size_t>(state.range(0));
  double t = 0;
  for (auto _ : state) {
    const auto batch = Batch(n, t);
    sink.InsertBatch(batch);
    t += 1000;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
}

void BM_PostgresInsertBatch(benchmark::State& state) {
  static testing::PostgresServer server;
  static const bool started = server.Start();
  if (!started) {
    state.SkipWithError(("PostgreSQL did not start: " + server.error()).c_str());
    return;
  }
  store::PostgresHistorySink sink({server.Url(), "bench"});
  InsertBatches(state, sink);
}
BENCHMARK(BM_PostgresInsertBatch)->Arg(64)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SqliteInsertBatch(benchmark::State& state) {
  const auto path = std::filesystem::temp_directory_path() / ("trueaxis_bench_" + std::to_string(::getpid()) + ".db");
  {
    store::HistoryDb db(path.string(), store::HistoryDb::Mode::kReadWrite);
    InsertBatches(state, db);
  }
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path.string() + suffix);
}
BENCHMARK(BM_SqliteInsertBatch)->Arg(64)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

// `range(0)` machines' status published (distinct topics), until the broker acknowledged all (QoS 1),
// with `range(1)` publishes in flight.
void BM_MqttPublishStatusQos1(benchmark::State& state) {
  static testing::MosquittoBroker broker;
  static const bool started = broker.Start();
  if (!started) {
    state.SkipWithError(("mosquitto did not start: " + broker.error()).c_str());
    return;
  }
  live::MqttPublisherOptions o;
  o.broker = broker.Uri();
  o.client_id = "bench";
  o.max_in_flight = static_cast<int>(state.range(1));
  live::MqttPublisher mqtt(o);
  const auto n = static_cast<int>(state.range(0));
  const std::string payload(300, 'x');  // a status JSON of ~300 bytes
  for (auto _ : state) {
    for (int m = 0; m < n; ++m) mqtt.Publish("m" + std::to_string(m), payload);
    if (!mqtt.Flush(60)) state.SkipWithError("not flushed in 60 s");
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["superseded"] = static_cast<double>(mqtt.Stats().superseded);
}
BENCHMARK(BM_MqttPublishStatusQos1)->Args({1000, 1})->Args({1000, 64})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
