#include "trueaxis/tooltherm/tool_report.hpp"

#include <cmath>

#include <fmt/format.h>

#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"

namespace trueaxis::tooltherm {
namespace {

constexpr std::size_t kMaxPoints = 1500;  // per series, so the page stays light

}  // namespace

std::string ToolDayReportHtml(const ToolTable& table, const ToolDayRecording& test, const ToolEvaluation& ev,
                              const std::string& subtitle) {
  report::HtmlPage page("Tool thermal error — virtual day");
  page.AddParagraph(subtitle);
  report::HtmlTable scores({"tool", "cutting samples", "hysteresis µm", "none", "one", "sub-models (seed 001)", "lag",
                            "two-body", "zones", "best"},
                           "RMS / max of the tip error while cutting, µm");
  for (const auto& sc : ev.tools) {
    std::vector<std::string> row = {fmt::format("T{}", sc.tool), std::to_string(sc.samples),
                                     fmt::format("{:.2f}", sc.curve_spread_um)};
    for (std::size_t k = 0; k < kToolModelKinds.size(); ++k) row.push_back(fmt::format("{:.2f} / {:.2f}", sc.rms_um[k], sc.max_um[k]));
    scores.AddRow(row);
  }
  page.AddTable(scores);
  const auto intervals = CompensatedResidualUm(ev.models, ToolModelKind::kIntervals, test, {});
  const auto best = CompensatedResidualUm(ev.models, ToolModelKind::kBest, test, {});
  for (const auto& t : table.tools) {
    const auto m = ev.models.find(t.number);
    if (m == ev.models.end()) continue;
    page.AddHeading(fmt::format("T{} {}", t.number, t.name));
    const auto rows = ToolRecordsOf(test, t.number);
    if (rows.empty()) continue;
    const ToolColumns cols = ColumnsOf(rows);
    const std::vector<double>&tv = cols.tv_c, &err = cols.error_um;
    const auto cls = ClassifySeries(cols.time_s, tv, cols.restart, m->second.classifier);
    const std::size_t step = std::max<std::size_t>(1, rows.size() / kMaxPoints);
    report::SvgChartOptions lo;
    lo.title = "true tip error against Tv, by interval (seed 001 classifier)";
    lo.x_label = "Tv (°C)";
    lo.y_label = "tip error (µm)";
    lo.y_includes_zero = false;
    report::SvgChart loop(lo);
    for (int k = 0; k < 4; ++k) {
      std::vector<double> x, y;
      for (std::size_t i = 0; i < rows.size(); i += step)
        if (static_cast<int>(cls[i]) == k) x.push_back(tv[i]), y.push_back(err[i]);
      if (!x.empty()) loop.AddPoints(thermal::ThermalIntervalName(static_cast<ThermalInterval>(k)), x, y);
    }
    page.AddChart(loop);
    report::SvgChartOptions to;
    to.title = "tip error over the test day (this tool mounted)";
    to.x_label = "time (h)";
    to.y_label = "µm";
    report::SvgChart time(to);
    std::vector<double> h, none, sub, bst;
    for (std::size_t i = 0; i < test.samples.size(); i += 1) {
      const auto& s = test.samples[i];
      if (s.tool != t.number) {
        if (!h.empty() && !std::isnan(none.back())) h.push_back(s.time_s / 3600), none.push_back(NAN), sub.push_back(NAN), bst.push_back(NAN);
        continue;
      }
      if (i % step) continue;
      h.push_back(s.time_s / 3600);
      none.push_back(s.true_error_um);
      sub.push_back(intervals[i]);
      bst.push_back(best[i]);
    }
    time.AddLine("no compensation", h, none).AddLine("seed 001 sub-models", h, sub).AddLine("best", h, bst);
    page.AddChart(time);
  }
  return page.Render();
}

}  // namespace trueaxis::tooltherm
