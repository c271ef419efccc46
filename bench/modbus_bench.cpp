// Round-trip cost of the MODBUS TCP links over loopback: what one compensator
// cycle pays to read the CNC's PMC window, write a compensation vector, and
// read an ADAM-6015's seven RTD channels. Server and client run in this
// process on 127.0.0.1 (two threads of the server + the benchmark thread).
//   ./build/bench/bench_modbus --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "../tests/support/mock_hardware.hpp"

namespace {

using namespace trueaxis;

// The shared mock hardware behind the server: three axes standing still, seven channels.
void MakeStill(testing::MockCnc& cnc, testing::MockTemperatures& temps) {
  for (std::size_t a = 0; a < 3; ++a) cnc.axes[a] = {100.0 * static_cast<double>(a) + 0.1234, 1, true};
  cnc.machine = {CoolantState::kFlood, true};
  for (std::size_t c = 0; c < 7; ++c) temps.values[c].temp_c = 20.0 + static_cast<double>(c);
}

struct Rig {
  testing::MockCnc cnc{{"X", "Y", "Z"}};
  testing::MockTemperatures temps{{"t0", "t1", "t2", "t3", "t4", "t5", "t6"}, 20.0};
  std::unique_ptr<drivers::ModbusMachineServer> server;
  std::unique_ptr<drivers::ModbusCncLink> link;
  std::unique_ptr<drivers::ModbusTemperatureSource> rtd;
  Rig() {
    MakeStill(cnc, temps);
    std::mt19937 rng(std::random_device{}());
    for (int i = 0; i < 50 && !server; ++i) {
      drivers::ModbusMachineServerOptions o;
      o.port = std::uniform_int_distribution<int>(20000, 59999)(rng);
      auto s = std::make_unique<drivers::ModbusMachineServer>(&cnc, &temps, o);
      std::string error;
      if (s->Start(&error)) server = std::move(s);
    }
    if (!server) return;
    drivers::ModbusCncLinkOptions lo;
    lo.endpoint.port = server->options().port;
    link = std::make_unique<drivers::ModbusCncLink>(lo);
    drivers::ModbusTemperatureSourceOptions to;
    to.endpoint.port = server->options().port;
    to.channel_names = {"a", "b", "c", "d", "e", "f", "g"};
    rtd = std::make_unique<drivers::ModbusTemperatureSource>(to);
  }
};

Rig& TheRig() {
  static Rig rig;
  return rig;
}

void BM_PmcWindowRead(benchmark::State& state) {
  auto& rig = TheRig();
  if (!rig.server) return state.SkipWithError("no free port");
  std::vector<hw::AxisState> axes(3);
  hw::CncState m;
  int failures = 0;
  for (auto _ : state) failures += !rig.link->Read(axes, m);
  state.counters["failures"] = failures;
}
BENCHMARK(BM_PmcWindowRead)->Unit(benchmark::kMicrosecond);

void BM_CompensationWrite(benchmark::State& state) {
  auto& rig = TheRig();
  if (!rig.server) return state.SkipWithError("no free port");
  std::vector<double> corr = {0, 0, 0};
  int failures = 0;
  for (auto _ : state) {
    corr[0] += 0.1;  // a new vector every time: the server forwards each one
    if (corr[0] > 100) corr[0] = -100;
    failures += !rig.link->WriteCompensation(corr);
  }
  state.counters["failures"] = failures;
}
BENCHMARK(BM_CompensationWrite)->Unit(benchmark::kMicrosecond);

void BM_CycleReadThenWrite(benchmark::State& state) {
  auto& rig = TheRig();
  if (!rig.server) return state.SkipWithError("no free port");
  std::vector<hw::AxisState> axes(3);
  hw::CncState m;
  std::vector<double> corr = {1, 2, 3};
  int failures = 0;
  for (auto _ : state) {
    failures += !rig.link->Read(axes, m);
    corr[1] = -corr[1];
    failures += !rig.link->WriteCompensation(corr);
  }
  state.counters["failures"] = failures;
}
BENCHMARK(BM_CycleReadThenWrite)->Unit(benchmark::kMicrosecond);

void BM_Adam6015Read7Channels(benchmark::State& state) {
  auto& rig = TheRig();
  if (!rig.server) return state.SkipWithError("no free port");
  std::vector<hw::RawTemperature> t(7);
  int failures = 0;
  for (auto _ : state) failures += !rig.rtd->Read(t);
  state.counters["failures"] = failures;
}
BENCHMARK(BM_Adam6015Read7Channels)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
