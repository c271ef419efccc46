// trueaxis analyze FILE [--standard NAME] [--json] [--report out.html]
//                       [--compare AFTER_FILE] [--lead-mm L] [--decompose]
// Evaluates a bidirectional positioning test (canonical CSV or ecmc .dat,
// detected by content) by ISO 230-2 / VDI 3441, optionally decomposes the
// error (seed 002) and writes a self-contained HTML report.
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "trueaxis/analysis/analysis_report.hpp"
#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/analysis/evaluation_json.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_file.hpp"

namespace trueaxis::cli {
namespace {

struct AnalyzeOptions {
  std::string file;
  std::string standard = "ISO 230-2:2014";
  bool json = false;
  std::string report;
  std::string compare;
  std::optional<double> lead_mm;
  bool decompose = false;
  int harmonics = 2;
  int trend_degree = 1;
  MeasurementInputOptions input;
};

// Lead from --lead-mm, else from a "lead_mm" metadata line, else 0 (unknown).
double ResolveLead(const AnalyzeOptions& o, const measure::Measurement& m) {
  if (o.lead_mm) {
    if (!std::isfinite(*o.lead_mm) || *o.lead_mm <= 0)
      throw InputError("--lead-mm", 0, "lead_mm", fmt::format("{} is not a positive screw lead in mm", *o.lead_mm));
    return *o.lead_mm;
  }
  if (auto meta = m.Meta("lead_mm")) {
    auto v = ParseDouble(*meta);
    if (!v || !std::isfinite(*v) || *v <= 0)
      throw InputError(m.source, m.MetaLine("lead_mm"), "lead_mm", fmt::format("metadata value '{}' is not a positive screw lead in mm", *meta));
    return *v;
  }
  return 0;
}

// A before/after comparison is only meaningful for the same test of the same
// axis: the same axis name (when both files say) and targets over mostly the
// same stretch of travel. Anything else is refused, naming what differs.
void RequireComparable(const measure::Measurement& before, const measure::Measurement& after) {
  const auto axis_b = before.Meta("axis"), axis_a = after.Meta("axis");
  if (axis_b && axis_a && *axis_b != *axis_a)
    throw InputError(after.source, after.MetaLine("axis"), "axis",
                     fmt::format("axis {} cannot be compared with {} of {}", *axis_a, *axis_b, before.source));
  const auto tb = before.Targets(), ta = after.Targets();
  if (tb.empty() || ta.empty()) return;
  const double lo = std::max(tb.front(), ta.front()), hi = std::min(tb.back(), ta.back());
  const double span = std::max(tb.back(), ta.back()) - std::min(tb.front(), ta.front());
  const double overlap = span > 0 ? std::max(0.0, hi - lo) / span : 1.0;
  if (overlap < 0.5)
    throw InputError(after.source, 0, "target_mm",
                     fmt::format("targets {}…{} mm ({} targets) overlap {:.0f} % of the travel of {}'s {}…{} mm ({} "
                                 "targets): not a before/after of the same test", FormatShortest(ta.front()),
                                 FormatShortest(ta.back()), ta.size(), 100 * overlap, before.source,
                                 FormatShortest(tb.front()), FormatShortest(tb.back()), tb.size()));
}

void RunAnalyze(const AnalyzeOptions& o) {
  analysis::EvaluationOptions eo;
  eo.standard = o.standard;
  std::string why;
  if (!eo.IsValid(&why)) throw InputError("--standard", 0, "standard", why);
  RefuseOutputOverInput(o.report, {o.file, o.compare, o.input.column_map}, "--report");

  const auto read = o.input.Resolve();
  const auto before = measure::ReadMeasurementFile(o.file, read);
  const auto warn_units = [](const measure::Measurement& m) {
    if (auto why = measure::DeviationUnitWarning(m)) fmt::print(stderr, "warning: {}: {}\n", m.source, *why);
  };
  warn_units(before);
  const auto ev = analysis::Evaluate(before, eo);

  std::unique_ptr<measure::Measurement> after_m;
  std::optional<analysis::Evaluation> after_ev;
  if (!o.compare.empty()) {
    after_m = std::make_unique<measure::Measurement>(measure::ReadMeasurementFile(o.compare, read));
    RequireComparable(before, *after_m);
    warn_units(*after_m);
    after_ev = analysis::Evaluate(*after_m, eo);
  }

  analysis::DecompositionOptions dopt;
  dopt.lead_mm = ResolveLead(o, before);
  dopt.harmonics = o.harmonics;
  dopt.trend_degree = o.trend_degree;
  if (!dopt.IsValid(&why)) throw InputError("command line", 0, "decomposition", why);
  const auto dec = analysis::Decompose(ev, dopt);
  const bool show_dec = o.decompose || dopt.lead_mm > 0;

  if (!o.report.empty()) {
    analysis::AnalysisReportInput in;
    in.before = {&before, &ev};
    if (after_ev) in.after = analysis::AnalyzedTest{after_m.get(), &*after_ev};
    in.decomposition = &dec;
    analysis::BuildAnalysisReport(in).Save(o.report);
  }

  if (o.json) {
    auto j = analysis::EvaluationToJson(ev);
    if (show_dec) j["decomposition"] = analysis::DecompositionToJson(dec);
    if (after_ev) j["compare"] = analysis::ComparisonToJson(ev, *after_ev);
    if (!o.report.empty()) j["report"] = o.report;
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << ev.FullReport();
  if (show_dec) std::cout << "\nError decomposition (progressive, periodic, random)\n" << dec.FullReport();
  if (after_ev) {
    std::cout << fmt::format("\nComparison with {} ({} targets × {} runs)\n", o.compare, after_ev->targets.size(),
                             after_ev->runs);
    std::cout << fmt::format("  {:<4} {:>10} {:>10} {:>10}\n", "", "before_um", "after_um", "change_um");
    const std::pair<const char*, double analysis::AxisResult::*> rows[] = {
        {"A", &analysis::AxisResult::A_um}, {"B", &analysis::AxisResult::B_um}, {"E", &analysis::AxisResult::E_um},
        {"M", &analysis::AxisResult::M_um}, {"R", &analysis::AxisResult::R_um}, {"P", &analysis::AxisResult::P_um}};
    for (const auto& [name, f] : rows)
      std::cout << fmt::format("  {:<4} {:>10.4f} {:>10.4f} {:>+10.4f}\n", name, ev.axis.*f, after_ev->axis.*f,
                               after_ev->axis.*f - ev.axis.*f);
  }
  if (!o.report.empty()) std::cout << "\nreport written to " << o.report << "\n";
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<AnalyzeOptions>();
  auto* cmd = app.add_subcommand("analyze", "Evaluate a positioning test by ISO 230-2 / VDI 3441 (CSV, ecmc .dat or a mapped laser export)");
  cmd->add_option("file", opts->file, "measurement file: canonical CSV or ecmc .dat (detected by content), or a laser software's CSV with --columns")->required();
  AddMeasurementInputOptions(cmd, opts->input);
  std::string names;
  for (const auto& n : analysis::StandardNames()) names += (names.empty() ? "" : ", ") + n;
  cmd->add_option("--standard", opts->standard, "evaluation standard: " + names)->capture_default_str();
  cmd->add_flag("--json", opts->json, "print one JSON object (µm) instead of the table");
  cmd->add_option("--report", opts->report, "write a self-contained HTML report to this path");
  cmd->add_option("--compare", opts->compare, "a second (after) measurement to compare against");
  cmd->add_option("--lead-mm", opts->lead_mm, "screw lead for the periodic part (default: 'lead_mm' metadata)");
  cmd->add_flag("--decompose", opts->decompose, "print the error decomposition even without a lead");
  cmd->add_option("--harmonics", opts->harmonics, "highest harmonic of the lead to fit (0..20)")->capture_default_str();
  cmd->add_option("--trend-degree", opts->trend_degree, "degree of the progressive trend (0..3)")->capture_default_str();
  cmd->callback([opts] { RunAnalyze(*opts); });
}

static CommandRegistrar reg("analyze", Setup);

}  // namespace
}  // namespace trueaxis::cli
