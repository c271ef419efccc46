// Cost of evaluating one positioning test: parse, ISO 230-2/VDI 3441 evaluation,
// decomposition and HTML report for a 5-run × 41-target file
// (examples/measurements/x_axis_ballscrew_5x41.csv, 410 points).
#include <benchmark/benchmark.h>

#include "trueaxis/analysis/analysis_report.hpp"
#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace {

const std::string& Text() {
  static const std::string text =
      trueaxis::ReadTextFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/measurements/x_axis_ballscrew_5x41.csv");
  return text;
}

void BM_ParseCsv_5x41(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(trueaxis::measure::ParseMeasurementCsv(Text(), "bench.csv"));
}
BENCHMARK(BM_ParseCsv_5x41);

void BM_Evaluate_5x41(benchmark::State& state) {
  const auto m = trueaxis::measure::ParseMeasurementCsv(Text(), "bench.csv");
  for (auto _ : state) benchmark::DoNotOptimize(trueaxis::analysis::Evaluate(m));
}
BENCHMARK(BM_Evaluate_5x41);

void BM_Decompose_5x41(benchmark::State& state) {
  const auto ev = trueaxis::analysis::Evaluate(trueaxis::measure::ParseMeasurementCsv(Text(), "bench.csv"));
  trueaxis::analysis::DecompositionOptions o;
  o.lead_mm = 50;  // resolvable with this spacing, so the least-squares path with harmonics runs
  o.harmonics = 1;
  for (auto _ : state) benchmark::DoNotOptimize(trueaxis::analysis::Decompose(ev, o));
}
BENCHMARK(BM_Decompose_5x41);

void BM_HtmlReport_5x41(benchmark::State& state) {
  const auto m = trueaxis::measure::ParseMeasurementCsv(Text(), "bench.csv");
  const auto ev = trueaxis::analysis::Evaluate(m);
  trueaxis::analysis::DecompositionOptions o;
  o.lead_mm = 10;
  const auto d = trueaxis::analysis::Decompose(ev, o);
  trueaxis::analysis::AnalysisReportInput in;
  in.before = {&m, &ev};
  in.decomposition = &d;
  std::size_t bytes = 0;
  for (auto _ : state) {
    auto html = trueaxis::analysis::BuildAnalysisReport(in).Render();
    bytes = html.size();
    benchmark::DoNotOptimize(html);
  }
  state.counters["html_bytes"] = static_cast<double>(bytes);
}
BENCHMARK(BM_HtmlReport_5x41);

}  // namespace

BENCHMARK_MAIN();
