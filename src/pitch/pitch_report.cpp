#include "trueaxis/pitch/pitch_report.hpp"

#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/analysis/analysis_report.hpp"
#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/analysis/evaluation.hpp"

namespace trueaxis::pitch {

namespace {

std::string F(double v) { return fmt::format("{:.3f}", v + 0.0); }

void MeansChart(report::HtmlPage& page, const std::string& title, const analysis::Evaluation& ev,
                const PitchErrorTable* table) {
  report::SvgChartOptions o;
  o.title = title;
  o.x_label = "position (mm)";
  o.y_label = "error (µm)";
  report::SvgChart chart(o);
  std::vector<double> x, up, down;
  for (const auto& t : ev.targets) {
    x.push_back(t.target_mm);
    up.push_back(t.mean_up_um);
    down.push_back(t.mean_down_um);
  }
  chart.AddPoints("measured mean ↑", x, up);
  chart.AddPoints("measured mean ↓", x, down);
  if (table) {
    report::SeriesStyle s;
    s.markers = true;
    chart.AddLine("table ↑ (linear between samples)", table->position_mm, table->error_up_um, s);
    chart.AddLine("table ↓", table->position_mm, table->error_down_um, s);
  }
  page.AddChart(chart);
}

}  // namespace

report::HtmlPage BuildPitchReport(const PitchReportInput& in) {
  if (!in.before || !in.after || !in.table) throw std::invalid_argument("pitch report: before, after and table are required");
  const auto& table = *in.table;
  const analysis::Evaluation before = analysis::Evaluate(*in.before);
  const analysis::Evaluation after = analysis::Evaluate(*in.after);
  analysis::DecompositionOptions d;
  d.lead_mm = table.lead_mm;
  const analysis::Decomposition dec = analysis::Decompose(before, d);
  analysis::AnalysisReportInput ai;
  ai.before = {in.before, &before};
  ai.after = analysis::AnalyzedTest{in.after, &after};
  ai.decomposition = &dec;
  report::HtmlPage page = analysis::BuildAnalysisReport(ai);

  const PitchComparison c = ComparePitch(*in.before, *in.after, table);
  page.AddHeading("Pitch error table (seed 002)");
  std::vector<std::pair<std::string, std::string>> kv = {
      {"axis", table.axis},
      {"lead", fmt::format("{} mm", table.lead_mm)},
      {"samples", fmt::format("{} ({} per lead, every {} mm), {} … {} mm", table.size(), table.samples_per_lead,
                              table.SpacingMm(), table.position_mm.front(), table.position_mm.back())},
      {"measured range (vouched for)",
       table.HasMeasuredRange() ? fmt::format("{} … {} mm", table.measured_from_mm, table.measured_to_mm)
                                : fmt::format("unknown (the file does not record it): the table's ends {} … {} mm",
                                              table.position_mm.front(), table.position_mm.back())},
      {"reference", fmt::format("{} mm", table.reference_mm)}};
  for (const auto& p : table.provenance) kv.emplace_back("provenance", p);
  page.AddKeyValueTable(kv);
  report::HtmlTable t({"µm", "before (every target)", "after (every target)", "before (lead points)", "after (lead points)"},
                      "seed 002's figures and ISO 230-2:2014");
  auto row = [&](const std::string& name, auto get) {
    t.AddRow({name, F(get(c.before)), F(get(c.after)), F(get(c.before_at_lead)), F(get(c.after_at_lead))});
  };
  row("maximum positioning error", [](const PositioningFigures& f) { return f.max_error_um; });
  row("error band 3σ (all readings)", [](const PositioningFigures& f) { return f.uncertainty_um; });
  row("repeatability 3σ (run to run)", [](const PositioningFigures& f) { return f.repeatability_3s_um; });
  row("A", [](const PositioningFigures& f) { return f.iso.A_um; });
  row("E", [](const PositioningFigures& f) { return f.iso.E_um; });
  row("R", [](const PositioningFigures& f) { return f.iso.R_um; });
  row("B", [](const PositioningFigures& f) { return f.iso.B_um; });
  page.AddTable(t);
  page.AddParagraph(fmt::format(
      "What is left: the table's interpolation error (largest difference between the calibration run's means and the "
      "table, at the targets between its samples) is {} µm; the repeatability (3σ run to run) after is {} µm; the "
      "drift (largest mean error after at the lead points, where the table is exact: thermal growth and reference "
      "changes between calibration and use) is {} µm: {} dominates the residual.",
      F(c.interpolation_error_um), F(c.after.repeatability_3s_um), F(c.drift_um), c.Dominant()));
  if (c.outside_targets > 0)
    page.AddParagraph(fmt::format(
        "Outside the range the table vouches for ({:g} … {:g} mm) the verification measured {} target(s), left out of "
        "the figures above: the table's end values were held there. Largest error there: {} µm before, {} µm after. "
        "Measure the whole travel the axis moves in.",
        c.vouched_from_mm, c.vouched_to_mm, c.outside_targets, F(c.outside_before_max_um), F(c.outside_after_max_um)));
  MeansChart(page, "Calibration run (before) and the table", before, &table);
  MeansChart(page, "Verification run (after): residual error", after, nullptr);
  if (!in.following.empty()) {
    report::HtmlTable ft({"feed (mm/min)", "ahead max (µm)", "ahead rms (µm)", "late max (µm)", "late rms (µm)"},
                         "following error of the correction: applied − exact, during a move");
    for (const auto& f : in.following)
      ft.AddRow({fmt::format("{:g}", f.feed_mm_min), F(f.ahead.max_abs_following_um), F(f.ahead.rms_following_um),
                 F(f.late.max_abs_following_um), F(f.late.rms_following_um)});
    page.AddTable(ft);
  }
  return page;
}

}  // namespace trueaxis::pitch
