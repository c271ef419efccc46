// Thermal model costs: training the seed 003 configuration (PSO init with 200
// particles + 500 BP epochs, 2-7-1) and prediction cost per sample for every
// model kind. Results: bench/results/thermal.md.
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

namespace {
using namespace trueaxis::thermal;

const ThermalSeries& ZTable() {
  static const ThermalSeries s = CleanSeries(
      SelectErrorChannels(ReadThermalSeriesCsv(std::string(TRUEAXIS_SOURCE_DIR) + "/data/thermal/seed003_z_axis.csv"),
                          {"mean"}),
      {}, nullptr);
  return s;
}

const ThermalSeries& FlTrain() {
  static const ThermalSeries s = [] {
    ThermalSeries all = CleanSeries(
        ImportFlThermalCsv(std::string(TRUEAXIS_SHARED_DATA_DIR) + "/fl_thermal/fl_thermal.csv"), {}, nullptr);
    auto blocks = SpeedBlocks(all);
    return SelectErrorChannels(SelectRows(all, RowsOfBlocks(blocks, ParseBlockList("0-8", 16, "b"))), {"ch1"});
  }();
  return s;
}

// Seed 003 exactly: 200 particles, 100 PSO iterations (our choice), 500 epochs, on the 10-point Z table.
void BM_Seed003Training_ZTable(benchmark::State& state) {
  PsoBpOptions o;
  for (auto _ : state) benchmark::DoNotOptimize(FitPsoBpNetwork(ZTable(), o));
}
BENCHMARK(BM_Seed003Training_ZTable)->Unit(benchmark::kMillisecond);

// The same configuration on one fl_thermal channel (7711 training rows; PSO fitness on 400 of them).
void BM_Seed003Training_FlThermalChannel(benchmark::State& state) {
  PsoBpOptions o;
  o.temperature_inputs = 2;
  for (auto _ : state) benchmark::DoNotOptimize(FitPsoBpNetwork(FlTrain(), o));
}
BENCHMARK(BM_Seed003Training_FlThermalChannel)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_Predict(benchmark::State& state, ModelKind kind) {
  static const ThermalSeries& s = FlTrain();
  ThermalFitOptions o;
  o.kind = kind;
  o.network.temperature_inputs = 2;
  o.network.particles = 20;  // prediction cost does not depend on training effort
  o.network.pso_iterations = 5;
  o.network.epochs = 5;
  auto model = FitThermalModel(s, o);
  std::vector<double> temps;
  for (const auto& n : model->InputSensors()) temps.push_back(s.temperatures_c(100, static_cast<Eigen::Index>(*s.TemperatureIndex(n))));
  std::vector<double> out(model->Channels().size());
  ThermalSample sample{temps, 0.0, ThermalInterval::kHeating};
  for (auto _ : state) {
    model->Predict(sample, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
}
BENCHMARK_CAPTURE(BM_Predict, mlr, ModelKind::kMlr);
BENCHMARK_CAPTURE(BM_Predict, ridge, ModelKind::kRidge);
BENCHMARK_CAPTURE(BM_Predict, pso_bp, ModelKind::kPsoBp);
BENCHMARK_CAPTURE(BM_Predict, hysteresis, ModelKind::kHysteresis);

}  // namespace

BENCHMARK_MAIN();
