// Cost of the command correction per block (seed 004's passes and the model inverse) (one block = one servo
// period of the corrected program), of the model prediction alone, and of
// the contour-error evaluation, on the example A/C machine's cone path.
//   ./build/bench/bench_fiveaxis --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include "trueaxis/fiveaxis/axis_identification.hpp"
#include "trueaxis/fiveaxis/command_correction.hpp"
#include "trueaxis/fiveaxis/contour_error.hpp"
#include "trueaxis/fiveaxis/interpolator.hpp"

namespace {
using namespace trueaxis::fiveaxis;

struct Setup {
  FiveAxisMachine machine = ReadFiveAxisMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/fiveaxis/table_ac.toml");
  Kinematics kin{machine.kinematics};
  TrackingErrorModel model = IdentifyTrackingModel(machine, AxisTestOptions{}, VirtualMachineRunner(machine));
  ToolPath path = MakeTestPath("cone", kin, 3000);
  Trajectory trajectory = Interpolate(path, machine);
};

const Setup& Get() {
  static const Setup s;
  return s;
}

void BM_CorrectionPerBlock(benchmark::State& state) {
  const Setup& s = Get();
  for (auto _ : state) {
    auto c = CorrectCommands(s.kin, s.model, s.trajectory.joints, s.trajectory.dt_s, 1.0, static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(c.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.trajectory.joints.size()));
  state.counters["blocks"] = static_cast<double>(s.trajectory.joints.size());
}
BENCHMARK(BM_CorrectionPerBlock)->Arg(1)->Arg(6)->Arg(16)->Unit(benchmark::kMillisecond);  // passes

void BM_ModelInversePerBlock(benchmark::State& state) {
  const Setup& s = Get();
  for (auto _ : state) {
    auto c = InvertTrackingModel(s.model, s.trajectory.joints, s.trajectory.dt_s, 1.0);
    benchmark::DoNotOptimize(c.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.trajectory.joints.size()));
}
BENCHMARK(BM_ModelInversePerBlock)->Unit(benchmark::kMillisecond);

void BM_PredictionPerBlock(benchmark::State& state) {
  const Setup& s = Get();
  for (auto _ : state) {
    auto e = PredictTrackingError(s.model, s.trajectory.joints, s.trajectory.dt_s, 1.0);
    benchmark::DoNotOptimize(e.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.trajectory.joints.size()));
}
BENCHMARK(BM_PredictionPerBlock)->Unit(benchmark::kMillisecond);

void BM_ContourErrorPerSample(benchmark::State& state) {
  const Setup& s = Get();
  for (auto _ : state) {
    auto c = EvaluateContour(s.path, s.kin, s.trajectory.joints);
    benchmark::DoNotOptimize(c.rms_um);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.trajectory.joints.size()));
}
BENCHMARK(BM_ContourErrorPerSample)->Unit(benchmark::kMillisecond);

void BM_IdentifyAllAxes(benchmark::State& state) {
  const Setup& s = Get();
  for (auto _ : state) {
    auto m = IdentifyTrackingModel(s.machine, AxisTestOptions{}, VirtualMachineRunner(s.machine));
    benchmark::DoNotOptimize(m.axes[0].fit_rms);
  }
}
BENCHMARK(BM_IdentifyAllAxes)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
