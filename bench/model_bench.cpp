// Cost of one model evaluation (the per-axis work of a compensation cycle).
#include <benchmark/benchmark.h>

#include "trueaxis/model/composite_model.hpp"

namespace {
using namespace trueaxis;
using namespace trueaxis::model;

AxisModel MakeAxis() {
  AxisModel a;
  a.axis = "X";
  a.key_sensors = {"nut", "bearing"};
  a.baseline_temp_c = {20, 20};
  a.ambient_sensor = "ambient";
  a.ambient_baseline_c = 20;
  a.rho_um_per_mm_per_c = 0.0115;
  for (auto& d : a.directions) {
    d.geometric.center_mm = 300;
    d.geometric.half_span_mm = 300;
    d.geometric.coefficients_um = {1, -4, 2, 0.5, -0.3, 0.1};
    d.thermal = {{CoolantState::kOff, {-0.01, -0.004}, 0}, {CoolantState::kFlood, {-0.006, -0.003}, 0}};
  }
  return a;
}

void BM_PredictPolynomialDegree5(benchmark::State& state) {
  const AxisModel axis = MakeAxis();
  const double temps[] = {24.5, 22.1};
  double x = 0;
  for (auto _ : state) {
    ThermalState s{temps, 21.0, CoolantState::kFlood, true};
    auto p = Predict(axis, x, Direction::kForward, s);
    benchmark::DoNotOptimize(p);
    x = x > 600 ? 0 : x + 0.37;
  }
}
BENCHMARK(BM_PredictPolynomialDegree5);
}  // namespace

BENCHMARK_MAIN();
