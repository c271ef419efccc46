#include "trueaxis/tooltherm/tool_evaluation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/median.hpp"
#include "trueaxis/tooltherm/tool_fallback.hpp"

namespace trueaxis::tooltherm {

std::map<int, ToolErrorModel> FitToolModels(const ToolTable& table, const ToolDayRecording& training,
                                            std::vector<std::string>* warnings) {
  std::map<int, ToolErrorModel> models;
  std::map<int, int> too_few;  // tool → its training rows
  // The sensor's factor on the free growth, shared by the tools of one machine and sensor: the
  // median of the whole zone slope per µm of free growth of the tools with enough rows for their own
  // zone slopes (first fit with the bare free growth); needs two such tools, else 1.
  std::vector<double> ratios;
  for (const auto& t : table.tools) {
    const auto rows = ToolRecordsOf(training, t.number);
    const auto g = ZoneGrowthUmPerC(t);
    if (rows.size() < kMinToolTrainingRows) {
      too_few[t.number] = static_cast<int>(rows.size());
      continue;
    }
    if (g.empty() || rows.size() < kMinZoneRowsPerCoefficient * (g.size() + 1)) continue;
    const ToolErrorModel m = FitToolErrorModel(t.number, rows, table.standard_temp_c, nullptr, g);
    if (m.zone_um_per_c.size() != g.size()) continue;
    double slope = 0, growth = 0;
    for (std::size_t z = 0; z < g.size(); ++z) slope += m.zone_um_per_c[z], growth += g[z];
    ratios.push_back(-slope / growth);
  }
  const double measured_factor = ratios.size() >= 2 ? Median(ratios) : 1.0;
  const double factor = std::clamp(measured_factor, kMinSensorGrowthFactor, kMaxSensorGrowthFactor);
  if (warnings && factor != measured_factor)
    warnings->push_back(fmt::format(
        "the sensors see {:.2f}× the tools' free growth per °C (median of {} tools), outside {:.1f}…{:.1f}: held at {:.2f} — "
        "check the emissivity setting and where the sensors look",
        measured_factor, ratios.size(), kMinSensorGrowthFactor, kMaxSensorGrowthFactor, factor));
  for (const auto& t : table.tools) {
    if (too_few.count(t.number)) continue;
    std::vector<double> g = ZoneGrowthUmPerC(t);
    for (double& v : g) v *= factor;
    models.emplace(t.number, FitToolErrorModel(t.number, ToolRecordsOf(training, t.number), table.standard_temp_c, warnings, g));
  }
  // A tool that cut too little gets a flagged stand-in from the others (tool_fallback.hpp).
  const std::map<int, ToolErrorModel> fitted = models;
  for (const auto& [number, rows] : too_few) {
    ToolErrorModel fallback;
    const bool made = FallbackModelFromOtherTools(*table.Find(number), fitted, table, rows, &fallback);
    if (made) models.emplace(number, fallback);
    if (!warnings) continue;
    std::string from;
    for (int f : fallback.fallback_from_tools) from += fmt::format("{}T{}", from.empty() ? "" : ", ", f);
    warnings->push_back(
        made ? fmt::format("tool {}: {} training samples (a model needs {}): a stand-in from the geometry and the models of "
                           "{} ({:+.2f} µm/°C), flagged — record this tool cutting to fit its own",
                           number, rows, kMinToolTrainingRows, from, fallback.one.per_c_um)
             : fmt::format("tool {}: {} training samples (a model needs {}) and no other tool to build a stand-in from: "
                           "no model, not compensated",
                           number, rows, kMinToolTrainingRows));
  }
  return models;
}

std::vector<double> CompensatedResidualUm(const std::map<int, ToolErrorModel>& models, ToolModelKind kind,
                                          const ToolDayRecording& test, const ToolOffsetOptions& options) {
  ToolOffsetCompensator comp(models, kind, options);
  std::vector<double> out;
  out.reserve(test.samples.size());
  for (const auto& s : test.samples) out.push_back(s.true_error_um + comp.Cycle(s.time_s, s.tool, s.tv_c, s.zone_c).applied_correction_um);
  return out;
}

ToolEvaluation EvaluateToolModels(const ToolTable& table, const ToolDayRecording& training, const ToolDayRecording& test,
                                  const ToolOffsetOptions& options) {
  ToolEvaluation ev;
  ev.models = FitToolModels(table, training, &ev.warnings);
  std::array<std::vector<double>, kToolModelKinds.size()> residual;
  for (ToolModelKind k : kToolModelKinds)
    residual[static_cast<std::size_t>(k)] = CompensatedResidualUm(ev.models, k, test, options);
  for (const auto& t : table.tools) {
    ToolScore sc;
    sc.tool = t.number;
    std::array<double, kToolModelKinds.size()> sum{};
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0;
    for (std::size_t i = 0; i < test.samples.size(); ++i) {
      const auto& s = test.samples[i];
      if (s.tool != t.number || !s.cutting) continue;
      ++sc.samples;
      for (std::size_t k = 0; k < kToolModelKinds.size(); ++k) {
        sum[k] += residual[k][i] * residual[k][i];
        sc.max_um[k] = std::max(sc.max_um[k], std::abs(residual[k][i]));
      }
      sx += s.tv_c;
      sy += s.true_error_um;
      sxx += s.tv_c * s.tv_c;
      sxy += s.tv_c * s.true_error_um;
      syy += s.true_error_um * s.true_error_um;
    }
    if (sc.samples == 0) continue;
    const double n = sc.samples;
    for (std::size_t k = 0; k < kToolModelKinds.size(); ++k) sc.rms_um[k] = std::sqrt(sum[k] / n);
    const double vx = sxx - sx * sx / n, vy = syy - sy * sy / n, cxy = sxy - sx * sy / n;
    sc.curve_spread_um = std::sqrt(std::max(0.0, (vx > 0 ? vy - cxy * cxy / vx : vy) / n));
    ev.tools.push_back(sc);
  }
  return ev;
}

}  // namespace trueaxis::tooltherm
