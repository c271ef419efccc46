// Cost of one compensation cycle (read temperatures + CNC through in-process
// fakes, condition, predict per axis, shape, write), reported per axis:
//   ./build/bench/bench_runtime --benchmark_min_time=0.5
// The counter per_axis = CPU time of one cycle / axes (shown with an SI prefix, e.g. 60n = 60 ns).
#include <cmath>

#include <benchmark/benchmark.h>

#include "../tests/runtime/fakes.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace {
using namespace trueaxis;
using namespace trueaxis::runtime;

// The timed loop both cycle benchmarks share: the axes sweep the travel, one temperature drifts,
// and each iteration is one full read → step → write cycle; reported per axis.
void RunCycles(benchmark::State& state, Compensator& comp, runtime::testing::MockCnc& cnc,
               runtime::testing::MockTemperatures& temps, int n_axes) {
  double t = 0, x = 0;
  for (auto _ : state) {
    x = x > 500 ? 0 : x + 0.37;
    for (int i = 0; i < n_axes; ++i) cnc.axes[static_cast<std::size_t>(i)] = {x + i, (i % 2) ? -1 : 1, true};
    temps.values[1].temp_c = 25 + 1e-4 * x;
    const auto& s = comp.RunCycle(cnc, temps, t += 0.01);
    benchmark::DoNotOptimize(s.axes[0].output_um);
  }
  state.counters["per_axis"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * n_axes, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// The mock machine of the cycle benchmarks: axes A, B, … and six temperature channels, unlocked.
struct CycleRig {
  static std::vector<std::string> AxisNames(int n) {
    std::vector<std::string> names;
    for (int i = 0; i < n; ++i) names.push_back(std::string(1, static_cast<char>('A' + i)));
    return names;
  }
  explicit CycleRig(int n_axes)
      : names(AxisNames(n_axes)),
        cnc(names, trueaxis::testing::MockLocking::kUnlocked),
        temps({"ambient", "nut", "bearing", "motor", "spindle", "coolant_tank"}, 22.0,
              trueaxis::testing::MockLocking::kUnlocked) {}
  std::vector<std::string> names;
  runtime::testing::MockCnc cnc;
  runtime::testing::MockTemperatures temps;
};

// range(0): axes; range(1): 0 = degree-2 polynomial Er(x), 1 = 35-point table (seed 002).
void BM_CompensationCycle(benchmark::State& state) {
  const int n_axes = static_cast<int>(state.range(0));
  const bool table = state.range(1) != 0;
  CycleRig rig(n_axes);
  auto& cnc = rig.cnc;
  auto& temps = rig.temps;
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  auto model = std::make_shared<model::CompositeModel>(*runtime::testing::TestModel(1.0, rig.names));
  if (table) {
    for (auto& a : model->axes)
      for (auto& d : a.directions) {
        d.geometric.kind = model::GeometricError::Kind::kTable;
        d.geometric.table_position_mm.clear();
        d.geometric.table_error_um.clear();
        for (int i = 0; i < 35; ++i) {
          d.geometric.table_position_mm.push_back(5 + 24.5 * i);
          d.geometric.table_error_um.push_back(3 * std::sin(i * 0.7));
        }
      }
  }
  comp->PublishModel(model, "bench");
  RunCycles(state, *comp, cnc, temps, n_axes);
}
BENCHMARK(BM_CompensationCycle)->ArgsProduct({{1, 3, 5, 8}, {0, 1}})->ArgNames({"axes", "table"});

// The worst case of the model's thermal state: every axis with a lag on both key sensors and,
// under flood coolant, a loss towards the room, so each key takes the observer (one exp per key).
// range(0): axes; range(1): coolant 0 = off (lag only), 1 = flood (lag + loss).
void BM_CompensationCycleThermalState(benchmark::State& state) {
  const int n_axes = static_cast<int>(state.range(0));
  CycleRig rig(n_axes);
  auto& cnc = rig.cnc;
  auto& temps = rig.temps;
  cnc.machine.coolant = state.range(1) ? CoolantState::kFlood : CoolantState::kOff;
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  auto model = std::make_shared<model::CompositeModel>(*runtime::testing::TestModel(1.0, rig.names));
  for (auto& a : model->axes) {
    a.key_lag_s = {600, 900};
    a.key_loss_s[static_cast<std::size_t>(CoolantState::kFlood)] = {300, 450};
  }
  comp->PublishModel(model, "bench");
  RunCycles(state, *comp, cnc, temps, n_axes);
}
BENCHMARK(BM_CompensationCycleThermalState)->ArgsProduct({{3}, {0, 1}})->ArgNames({"axes", "flood"});

// A model with fallbacks (AxisModel::fallbacks, issue 10): every axis lagged as above plus two
// fallbacks (without the nut, without the bearing), each with its own lag, advanced every cycle
// alongside the model. range(1): 0 = every key reads (the fallbacks only advanced), 1 = the nut lost
// (its fallback predicts), 2 = the nut lost with a second fallback replacing it (the two averaged,
// as the fit writes them: AxisModel::replaces).
void BM_CompensationCycleFallbacks(benchmark::State& state) {
  const int n_axes = static_cast<int>(state.range(0));
  CycleRig rig(n_axes);
  auto& cnc = rig.cnc;
  auto& temps = rig.temps;
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  auto model = std::make_shared<model::CompositeModel>(*runtime::testing::TestModel(1.0, rig.names));
  for (auto& a : model->axes) {
    a.key_lag_s = {600, 900};
    std::vector<std::pair<std::vector<std::string>, std::string>> fallbacks = {{{"bearing", "motor"}, "nut"},
                                                                               {{"nut", "motor"}, "bearing"}};
    if (state.range(1) == 2) fallbacks.push_back({{"motor", "bearing"}, "nut"});
    for (const auto& [keys, replaces] : fallbacks) {
      model::AxisModel f = a;
      f.key_sensors = keys;
      f.baseline_temp_c = {22, 22};
      f.key_lag_s = {900, 1200};
      f.replaces = replaces;
      a.fallbacks.push_back(std::move(f));
    }
  }
  comp->PublishModel(model, "bench");
  if (state.range(1)) temps.SetFault("nut", true);  // never read: lost from the first cycle
  RunCycles(state, *comp, cnc, temps, n_axes);
}
BENCHMARK(BM_CompensationCycleFallbacks)->ArgsProduct({{3}, {0, 1, 2}})->ArgNames({"axes", "nut_lost"});

void BM_ModelSwapPickup(benchmark::State& state) {
  // Publish (off-loop bind) + the cycle that picks it up.
  runtime::testing::MockCnc cnc({"X", "Y", "Z"}, trueaxis::testing::MockLocking::kUnlocked);
  runtime::testing::MockTemperatures temps({"ambient", "nut", "bearing"}, 22.0, trueaxis::testing::MockLocking::kUnlocked);
  auto comp = Compensator::ForHardware(CompensatorOptions{}, cnc, temps, {});
  auto m = runtime::testing::TestModel(1.0, {"X", "Y", "Z"});
  double t = 0;
  for (auto _ : state) {
    comp->PublishModel(m, "bench");
    benchmark::DoNotOptimize(comp->RunCycle(cnc, temps, t += 0.01).model_id);
  }
}
BENCHMARK(BM_ModelSwapPickup);
}  // namespace

BENCHMARK_MAIN();
