#include "trueaxis/modelfit/fit_report.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/text_file.hpp"
#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"

namespace trueaxis::model {
namespace {

std::string Num(double v, int decimals = 3) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, decimals) : "–"; }

// Mean measured deviation per target of one direction.
void MeansOf(const measure::Measurement& m, Direction d, std::vector<double>& x, std::vector<double>& y) {
  std::map<long long, std::pair<double, int>> acc;  // key: target in nm
  std::map<long long, double> pos;
  for (const auto& p : m.points) {
    if (p.direction != d) continue;
    const long long k = std::llround(p.target_mm * 1e6);
    acc[k].first += p.deviation_um;
    acc[k].second += 1;
    pos[k] = p.target_mm;
  }
  for (const auto& [k, v] : acc) {
    x.push_back(pos[k]);
    y.push_back(v.first / v.second);
  }
}

// The model's curve for a state: each target's prediction with the mean
// temperatures of that target's points (what the runtime would have applied).
void ModelCurve(const AxisModel& a, const FitState& s, Direction d, std::vector<double>& x, std::vector<double>& y) {
  std::map<long long, std::pair<double, int>> acc;
  std::map<long long, double> pos;
  for (const auto& p : s.measurement.points) {
    if (p.direction != d) continue;
    const auto t = TemperaturesForPoint(a, s.measurement, p);
    const double pred = Predict(a, p.target_mm, d, {t.key_temp_c, t.ambient_c, s.coolant, true}).total_um;
    const long long k = std::llround(p.target_mm * 1e6);
    acc[k].first += pred;
    acc[k].second += 1;
    pos[k] = p.target_mm;
  }
  for (const auto& [k, v] : acc) {
    x.push_back(pos[k]);
    y.push_back(v.first / v.second);
  }
}

}  // namespace

std::string RenderFitReportHtml(const FitResult& result, const std::vector<FitState>& states) {
  const auto& m = result.model;
  report::HtmlPage page(fmt::format("Composite error model fit{}", m.machine.empty() ? "" : " — " + m.machine));
  page.AddNote("Values are errors (actual − commanded, µm); the correction is −error (docs/sign-convention.md). "
               "Model: Er(x,T) = Er(x) + tanβ·(Px − P0) + ρ·ΔT_env·(Px − P0), tanβ = Σ k_i·ΔT_i, per direction.");
  page.AddKeyValueTable({{"machine", m.machine.empty() ? "–" : m.machine},
                         {"created (UTC)", m.created_utc},
                         {"revision", std::to_string(m.revision)},
                         {"parent sha256", m.parent_sha256.empty() ? "–" : m.parent_sha256},
                         {"source files", std::to_string(m.sources.size())}});

  for (std::size_t ai = 0; ai < m.axes.size() && ai < result.summary.axes.size(); ++ai) {
    const auto& a = m.axes[ai];
    const auto& sum = result.summary.axes[ai];
    page.AddHeading(fmt::format("Axis {}", a.axis), 2);
    page.AddKeyValueTable(
        {{"cold state", sum.cold_source},
         {"reference point Px", fmt::format("{} mm ({})", Num(a.reference_position_mm, 2), sum.reference_source)},
         {"ρ", fmt::format("{} µm/mm/°C ({})", Num(a.rho_um_per_mm_per_c, 6), sum.rho_source)},
         {"key sensors", a.key_sensors.empty() ? "none (geometric only)" : fmt::format("{}", fmt::join(a.key_sensors, ", "))},
         {"why these", sum.key_selection_reason},
         {"thermal CV RMS", fmt::format("{} µm (without thermal term {} µm)", Num(sum.thermal_cv_rms_um),
                                        Num(sum.no_thermal_cv_rms_um))}});

    page.AddHeading("Geometric part Er(x)", 3);
    for (int d = 0; d < 2; ++d) {
      const auto& ds = sum.directions[d];
      page.AddParagraph(fmt::format("{} direction: {}", d == 0 ? "forward (+)" : "reverse (−)", ds.choice));
      if (!ds.degree.candidates.empty()) {
        report::HtmlTable t({"degree", "fit RMS (µm)", "leave-one-target-out CV RMS (µm)", "chosen"},
                            fmt::format("{} direction: {}", d == 0 ? "forward (+)" : "reverse (−)", ds.degree.rule));
        for (const auto& c : ds.degree.candidates)
          t.AddRow({std::to_string(c.degree), Num(c.fit_rms_um), Num(c.cv_rms_um),
                    c.degree == ds.degree.degree && ds.kind == GeometricError::Kind::kPolynomial ? "✔" : ""});
        page.AddTable(t);
      }
      if (ds.kind == GeometricError::Kind::kTable) {
        page.AddParagraph(fmt::format("{} direction: sampled table of {} targets (seed 002), CV RMS {} µm",
                                      d == 0 ? "forward" : "reverse", ds.targets, Num(ds.table_cv_rms_um)));
      }
    }
    if (!sum.selection_steps.empty()) {
      page.AddHeading("Key-sensor selection", 3);
      report::HtmlTable t({"sensors", "leave-one-state-out CV RMS (µm)", "step"});
      for (const auto& s : sum.selection_steps)
        t.AddRow({s.keys.empty() ? "(none)" : fmt::format("{}", fmt::join(s.keys, ", ")), Num(s.cv_rms_um), s.note});
      page.AddTable(t);
      if (!sum.motion_reason.empty()) page.AddNote("motion heat: " + sum.motion_reason);
      for (const auto& n : sum.coolant_notes) page.AddNote(n);
      for (const auto& n : sum.fallback_notes) page.AddNote(n);
    }
    if (!a.key_sensors.empty()) {
      std::vector<std::string> header{"coolant", "direction"};
      for (const auto& k : a.key_sensors) header.push_back("k " + k + " (µm/mm/°C)");
      if (a.HasMotionHeat())
        header.push_back(fmt::format("k motion heat, τ {} s (µm/mm per m/min)", Num(a.motion_lag_s, 0)));
      report::HtmlTable t(header, "Gains (the coolant look-up table)");
      for (int d = 0; d < 2; ++d)
        for (const auto& g : a.directions[d].thermal) {
          std::vector<std::string> row{std::string(CoolantStateName(g.coolant)), d == 0 ? "+" : "−"};
          for (double k : g.k_um_per_mm_per_c) row.push_back(Num(k, 6));
          t.AddRow(row);
        }
      page.AddTable(t);
    }

    page.AddHeading("States: measured vs model", 3);
    report::HtmlTable st({"state", "kind", "coolant", "points", "uncorrected RMS", "uncorrected max", "residual RMS",
                          "residual max", "tanβ + (µm/mm)", "tanβ − (µm/mm)"},
                         "residual = measured − model at each point's own temperatures (µm)");
    for (const auto& s : sum.states)
      st.AddRow({s.label, StateKindName(s.kind), std::string(CoolantStateName(s.coolant)), std::to_string(s.points),
                 Num(s.uncorrected_rms_um), Num(s.uncorrected_max_um), Num(s.residual_rms_um), Num(s.residual_max_um),
                 Num(s.tan_beta_um_per_mm[0], 5), Num(s.tan_beta_um_per_mm[1], 5)});
    page.AddTable(st);

    if (!sum.diagnosis.states.empty()) {
      const auto& dg = sum.diagnosis;
      page.AddHeading("What the residual shows", 3);
      report::HtmlTable rt({"state", "points", "offset (µm)", "slope (µm/m)", "end to end (µm)", "pattern RMS (µm)",
                            "residual RMS (µm)"},
                           fmt::format("{} residual split along the travel; noise levels: offset {} µm, end-to-end "
                                       "slope {} µm ({})",
                                       dg.cross_validated ? "cross-validated" : "in-sample", Num(dg.offset_level_um, 2),
                                       Num(dg.slope_level_um, 2), dg.noise_source));
      for (const auto& s : dg.states)
        rt.AddRow({s.label + (s.cold ? " (cold)" : ""), std::to_string(s.points), Num(s.offset_um, 2),
                   Num(s.slope_um_per_m, 1), Num(s.end_to_end_um, 2), Num(s.pattern_rms_um, 2), Num(s.residual_rms_um, 2)});
      page.AddTable(rt);
      for (const auto& f : dg.findings) page.AddParagraph(f);
      if (!dg.key_shares.empty()) {
        report::HtmlTable kt({"key sensor", "RMS of its correction (µm)", "share of the thermal correction (%)"});
        for (const auto& k : dg.key_shares) kt.AddRow({k.sensor, Num(k.rms_um, 2), Num(k.share_pct, 1)});
        page.AddTable(kt);
      }
    }

    for (const auto& s : states) {
      const std::string axis = s.axis.empty() ? a.axis : s.axis;
      if (axis != a.axis) continue;
      report::SvgChartOptions co;
      co.title = fmt::format("{} — {}", s.label.empty() ? s.path : s.label, s.path);
      co.x_label = "target position (mm)";
      co.y_label = "error (µm)";
      report::SvgChart chart(co);
      for (Direction d : {Direction::kForward, Direction::kReverse}) {
        std::vector<double> mx, my, px, py;
        MeansOf(s.measurement, d, mx, my);
        ModelCurve(a, s, d, px, py);
        const bool fwd = d == Direction::kForward;
        report::SeriesStyle line;
        line.color = fwd ? "#1f77b4" : "#d62728";
        report::SeriesStyle dots = line;
        dots.marker_radius_px = 3.5;
        chart.AddPoints(fwd ? "measured + (mean)" : "measured − (mean)", mx, my, dots);
        chart.AddLine(fwd ? "model +" : "model −", px, py, line);
      }
      page.AddChart(chart);
    }
  }
  if (!result.summary.warnings.empty()) {
    page.AddHeading("Warnings", 2);
    for (const auto& w : result.summary.warnings) page.AddParagraph(w);
  }
  page.AddHeading("Data the model came from", 2);
  report::HtmlTable src({"file", "state", "sha256 (first 16 hex; full in the model file)"});
  for (const auto& s : m.sources) src.AddRow({s.path, s.state, s.sha256.substr(0, 16)});
  page.AddTable(src);
  page.AddHeading("Full fit report", 2);
  page.AddRawHtml("<pre>" + report::EscapeHtml(result.summary.FullReport()) + "</pre>");
  return page.Render();
}

void WriteFitReportHtml(const FitResult& result, const std::vector<FitState>& states, const std::string& path) {
  WriteTextFile(path, RenderFitReportHtml(result, states));
}

}  // namespace trueaxis::model
