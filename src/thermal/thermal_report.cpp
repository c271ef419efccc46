// HTML report of a thermal model evaluation (uses the shared report module).
#include <algorithm>
#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"
#include "trueaxis/thermal/model_fitting.hpp"

namespace trueaxis::thermal {
namespace {

// At most ~max_points evenly spaced rows, so a 46 h series stays a light page.
std::vector<Eigen::Index> PlotRows(Eigen::Index n, Eigen::Index max_points) {
  std::vector<Eigen::Index> rows;
  const Eigen::Index stride = std::max<Eigen::Index>(1, (n + max_points - 1) / max_points);
  for (Eigen::Index r = 0; r < n; r += stride) rows.push_back(r);
  if (!rows.empty() && rows.back() != n - 1) rows.push_back(n - 1);
  return rows;
}

}  // namespace

void WriteThermalReport(const ThermalEvaluation& ev, const std::string& path) {
  const ThermalSeries& s = ev.series;
  report::HtmlPage page("Thermal error models — " + s.source);
  page.AddHeading("Data and split");
  page.AddKeyValueTable({{"series", s.source},
                         {"rows", std::to_string(s.Rows())},
                         {"temperatures", fmt::format("{}", fmt::join(s.temperature_names, ", "))},
                         {"error channels", fmt::format("{}", fmt::join(s.error_names, ", "))},
                         {"cleaning", ev.cleaning.BriefReport()}});
  {  // one paragraph per line (a leave-one-experiment-out split lists its folds)
    std::istringstream lines(ev.SplitDescription());
    for (std::string line; std::getline(lines, line);)
      if (!line.empty()) page.AddParagraph(line);
  }
  report::HtmlTable blocks({"block", "spindle (rpm)", "start (h)", "end (h)", "rows", "role"});
  for (const auto& b : ev.blocks) {
    const bool tr = std::find(ev.train_blocks.begin(), ev.train_blocks.end(), b.index) != ev.train_blocks.end();
    const bool va = std::find(ev.validate_blocks.begin(), ev.validate_blocks.end(), b.index) != ev.validate_blocks.end();
    blocks.AddRow({std::to_string(b.index), fmt::format("{}", b.spindle_rpm), fmt::format("{:.2f}", b.start_s / 3600),
                   fmt::format("{:.2f}", b.end_s / 3600), std::to_string(b.last_row - b.first_row + 1),
                   tr && va ? "train+validate" : tr ? "train" : va ? "validate" : "-"});
  }
  page.AddTable(blocks);

  page.AddHeading("Residuals (µm)");
  page.AddNote("residual = measured − predicted; 'no compensation' is the measured error itself");
  report::HtmlTable metrics({"model", "channel", "train RMSE", "train max |e|", "validation RMSE", "validation max |e|"});
  auto add = [&](const std::string& name, const std::vector<ChannelMetrics>& tr, const std::vector<ChannelMetrics>& va) {
    for (std::size_t c = 0; c < tr.size(); ++c)
      metrics.AddRow({name, tr[c].channel, fmt::format("{:.3f}", tr[c].rmse_um), fmt::format("{:.3f}", tr[c].max_abs_um),
                      fmt::format("{:.3f}", va[c].rmse_um), fmt::format("{:.3f}", va[c].max_abs_um)});
  };
  add("no compensation", ev.baseline_train, ev.baseline_validate);
  add("constant (train mean)", ev.constant_train, ev.constant_validate);
  for (const auto& m : ev.models) add(m.name, m.train, m.validate);
  page.AddTable(metrics);
  page.AddNote("'constant' predicts the training mean of each channel's error: a model that does not beat it "
               "only removes an offset");

  page.AddHeading("Models and chosen sensors");
  for (const auto& m : ev.models) {
    page.AddHeading(fmt::format("{} (fitted in {:.2f} s)", m.name, m.fit_seconds), 3);
    page.AddKeyValueTable({{"input sensors", fmt::format("{}", fmt::join(m.model->InputSensors(), ", "))}});
    page.AddRawHtml("<pre style=\"white-space:pre-wrap\">" + report::EscapeHtml(m.model->Describe() + m.fit_report) + "</pre>");
  }

  const std::vector<Eigen::Index> rows = PlotRows(s.Rows(), 1500);
  // Several experiments are drawn one after the other on one time axis (without the gap that
  // separates them in the joined series), with a marker where each begins.
  std::vector<double> row_x(static_cast<std::size_t>(s.Rows()));
  std::vector<std::pair<double, std::string>> experiment_starts;
  {
    double offset_h = 0, start_s = s.Rows() ? s.time_s[0] : 0.0;
    for (Eigen::Index r = 0; r < s.Rows(); ++r) {
      const auto ru = static_cast<std::size_t>(r);
      if (s.ExperimentCount() > 1 && (r == 0 || s.ExperimentOf(r) != s.ExperimentOf(r - 1))) {
        if (r > 0)  // one sample step after the previous experiment's last row
          offset_h = row_x[ru - 1] + (ru >= 2 ? (s.time_s[ru - 1] - s.time_s[ru - 2]) / 3600.0 : 0.0);
        start_s = s.time_s[ru];
        experiment_starts.emplace_back(offset_h, s.experiment_names[static_cast<std::size_t>(s.ExperimentOf(r))]);
      }
      row_x[ru] = !s.has_time ? static_cast<double>(r)
                  : s.ExperimentCount() > 1 ? offset_h + (s.time_s[ru] - start_s) / 3600.0
                                            : s.time_s[ru] / 3600.0;
    }
  }
  std::vector<double> x;
  for (Eigen::Index r : rows) x.push_back(row_x[static_cast<std::size_t>(r)]);
  const std::string x_label = !s.has_time ? "sample" : s.ExperimentCount() > 1 ? "time, experiments end to end (h)" : "time (h)";
  double split_x = NAN;
  if (!ev.in_sample && !ev.validate_rows.empty() && s.has_time && ev.folds.size() == 1)
    split_x = row_x[static_cast<std::size_t>(ev.validate_rows.front())];
  // Where the rows switch between training and validation: a marker on every chart.
  std::vector<std::pair<double, bool>> switches;  // x, true = validation starts
  if (!ev.in_sample && !ev.validate_rows.empty() && ev.folds.size() == 1) {
    std::vector<bool> is_validation(static_cast<std::size_t>(s.Rows()), false);
    for (auto r : ev.validate_rows) is_validation[static_cast<std::size_t>(r)] = true;
    for (Eigen::Index r = 1; r < s.Rows(); ++r)
      if (is_validation[static_cast<std::size_t>(r)] != is_validation[static_cast<std::size_t>(r - 1)])
        switches.emplace_back(row_x[static_cast<std::size_t>(r)], is_validation[static_cast<std::size_t>(r)]);
  }
  auto mark_split = [&](report::SvgChart& chart) {
    for (std::size_t e = 0; e < experiment_starts.size(); ++e)
      chart.AddVerticalLine(e == 0 ? "experiment starts" : "", experiment_starts[e].first,
                            report::SeriesStyle{"#E68310", 1.2, true});
    bool labelled_v = false, labelled_t = false;
    for (const auto& [sx, validation] : switches) {
      report::SeriesStyle st{validation ? "#7F3C8D" : "#11A579", 1.4, true};
      std::string label;
      if (validation && !labelled_v) label = "validation starts", labelled_v = true;
      if (!validation && !labelled_t) label = "training starts", labelled_t = true;
      chart.AddVerticalLine(label, sx, st);
    }
  };
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    const std::string ch = s.error_names[static_cast<std::size_t>(c)];
    page.AddHeading("Channel " + ch);
    if (std::isfinite(split_x)) page.AddNote(fmt::format("validation starts at {:.2f} h", split_x));
    report::SvgChartOptions o;
    o.title = ch + ": measured and predicted error";
    o.x_label = x_label;
    o.y_label = "error (µm)";
    report::SvgChart chart(o);
    std::vector<double> y;
    for (Eigen::Index r : rows) y.push_back(s.errors_um(r, c));
    report::SeriesStyle measured;
    measured.color = "#000000";
    measured.width_px = 2.2;
    chart.AddLine("measured", x, y, measured);
    for (const auto& m : ev.models) {
      std::vector<double> yp;
      for (Eigen::Index r : rows) yp.push_back(m.predicted_um(r, c));
      chart.AddLine(m.name, x, yp);
    }
    mark_split(chart);
    page.AddChart(chart);
    report::SvgChartOptions ro = o;
    ro.title = ch + ": residual (measured − predicted)";
    ro.y_label = "residual (µm)";
    report::SvgChart res(ro);
    res.AddLine("no compensation", x, y, report::SeriesStyle{"#999999", 1.2, true});
    for (const auto& m : ev.models) {
      std::vector<double> yr;
      for (Eigen::Index r : rows) yr.push_back(s.errors_um(r, c) - m.predicted_um(r, c));
      res.AddLine(m.name, x, yr);
    }
    mark_split(res);
    page.AddChart(res);
  }

  // Temperatures the models use.
  std::vector<std::string> used;
  for (const auto& m : ev.models)
    for (const auto& n : m.model->InputSensors())
      if (std::find(used.begin(), used.end(), n) == used.end()) used.push_back(n);
  if (!used.empty()) {
    page.AddHeading("Chosen temperature sensors");
    report::SvgChartOptions o;
    o.title = "temperatures used by the models";
    o.x_label = x_label;
    o.y_label = "temperature (°C)";
    o.y_includes_zero = false;
    report::SvgChart chart(o);
    for (const auto& n : used) {
      auto idx = s.TemperatureIndex(n);
      if (!idx) continue;
      std::vector<double> y;
      for (Eigen::Index r : rows) y.push_back(s.temperatures_c(r, static_cast<Eigen::Index>(*idx)));
      chart.AddLine(n, x, y);
    }
    page.AddChart(chart);
  }
  page.Save(path);
}

}  // namespace trueaxis::thermal
