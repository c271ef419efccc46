// Speed of the tool thermal chain (docs/tool-thermal.md): Tv from one camera frame, one
// compensation cycle (classifier + model + limiter), one per-tool fit. Accuracy is in
// bench/results/tool_thermal.md (trueaxis tool day, bench/tool_thermal_days.py).
#include <benchmark/benchmark.h>

#include "trueaxis/tooltherm/tool_evaluation.hpp"

namespace {
using namespace trueaxis::tooltherm;

ToolDescription Tool() {
  ToolDescription t;
  t.number = 1;
  t.length_mm = 60;
  t.diameter_mm = 10;
  t.holder_length_mm = 60;
  t.holder_diameter_mm = 40;
  t.zones = DefaultToolZones(t);
  return t;
}

void BM_TvFromFrame(benchmark::State& state) {
  VirtualTool vt(Tool(), 20, 20);
  for (int i = 0; i < 300; ++i) vt.Advance(1, {true, 22, 8000, 1200, false, 20, 20});
  ThermalCameraOptions o;
  std::mt19937_64 rng(1);
  const cv::Mat img = RenderThermalImage(vt, {}, o, rng);
  const ZoneFile zf{"geometry", ImageZonesFor(vt.tool(), o)};
  const auto areas = ZoneAreas(zf.zones);
  for (auto _ : state) benchmark::DoNotOptimize(WeightedMeanTemperatureC(ZoneMeansC(img, zf, "frame"), areas));
  state.SetLabel(std::to_string(img.cols) + "x" + std::to_string(img.rows) + " px");
}
BENCHMARK(BM_TvFromFrame);

struct Day {
  ToolTable table = RandomToolTable(2, 7);
  ToolDayRecording rec;
  Day() {
    ToolDayOptions o;
    o.hours = 2;
    o.sample_s = 2;
    rec = RunToolDay(table, o);
  }
};
const Day& SharedDay() {
  static const Day d;
  return d;
}

void BM_FitOneTool(benchmark::State& state) {
  const auto rows = ToolRecordsOf(SharedDay().rec, 1);
  for (auto _ : state) benchmark::DoNotOptimize(FitToolErrorModel(1, rows, 20));
  state.SetLabel(std::to_string(rows.size()) + " rows");
}
BENCHMARK(BM_FitOneTool)->Unit(benchmark::kMillisecond);

void BM_OffsetCycle(benchmark::State& state) {
  const Day& d = SharedDay();
  const auto models = FitToolModels(d.table, d.rec, nullptr);
  ToolOffsetCompensator comp(models, static_cast<ToolModelKind>(state.range(0)));
  std::size_t i = 0;
  double t = 0;
  for (auto _ : state) {
    const auto& s = d.rec.samples[i];
    benchmark::DoNotOptimize(comp.Cycle(t, s.tool, s.tv_c, s.zone_c));
    t += 2;
    if (++i == d.rec.samples.size()) i = 0;
  }
  state.SetLabel(ToolModelKindName(static_cast<ToolModelKind>(state.range(0))));
}
BENCHMARK(BM_OffsetCycle)->DenseRange(1, 6);

}  // namespace

BENCHMARK_MAIN();
