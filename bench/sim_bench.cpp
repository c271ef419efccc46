// Speed of the virtual machine: simulated machine time per wall second, and
// the wall time of a laser measurement and of a full campaign.
//   ./build/bench/bench_sim --benchmark_min_time=1
#include <filesystem>

#include <benchmark/benchmark.h>

#include "trueaxis/sim/campaign.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace {

const trueaxis::sim::MachineDescription& Vmc850() {
  static const auto m = trueaxis::sim::ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
  return m;
}

// One hour of warm-up (all three axes reciprocating) per iteration.
void BM_WarmUpHour(benchmark::State& state) {
  trueaxis::sim::VirtualMachine vm(Vmc850(), 1);
  for (std::size_t i = 0; i < vm.AxisCount(); ++i)
    vm.CommandReciprocate(i, 10, Vmc850().axes[i].travel_mm - 10, 2000, 1.0, 4000);
  for (auto _ : state) {
    vm.Advance(3600);
    benchmark::DoNotOptimize(vm.ErrorUm(0));
  }
  state.counters["sim_hours_per_wall_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_WarmUpHour)->Unit(benchmark::kMillisecond);

// A day of standstill (IdleUntil, coarse steps).
void BM_IdleDay(benchmark::State& state) {
  trueaxis::sim::VirtualMachine vm(Vmc850(), 1);
  for (auto _ : state) vm.IdleUntil(vm.TimeS() + 86400);
  state.counters["sim_hours_per_wall_s"] =
      benchmark::Counter(24.0 * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_IdleDay)->Unit(benchmark::kMillisecond);

// ISO 230-2 test of X: 35 targets × 2 directions × 5 runs (~22 min machine time).
void BM_LaserMeasurementX(benchmark::State& state) {
  trueaxis::sim::VirtualMachine vm(Vmc850(), 1);
  trueaxis::sim::LaserInterferometer laser({}, 1);
  laser.Setup(vm, 0, 0);
  for (auto _ : state) benchmark::DoNotOptimize(laser.Measure(vm).points.size());
}
BENCHMARK(BM_LaserMeasurementX)->Unit(benchmark::kMillisecond);

// The default campaign on all three axes, files written to a temp dir.
void BM_CampaignVmc850(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "trueaxis_bench_campaign";
  double machine_h = 0;
  for (auto _ : state) {
    trueaxis::sim::CampaignOptions o;
    o.out_dir = dir.string();
    machine_h = trueaxis::sim::RunCampaign(Vmc850(), o).machine_time_s / 3600.0;
  }
  state.counters["machine_time_h"] = machine_h;
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_CampaignVmc850)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
