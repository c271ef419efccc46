#include "trueaxis/analysis/analysis_report.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::analysis {
namespace {

using report::HtmlTable;
using report::SeriesStyle;
using report::SvgChart;
using report::SvgChartOptions;

constexpr const char* kUp = "#0072B2";    // forward (+)
constexpr const char* kDown = "#D55E00";  // reverse (−)

std::string Um(double v) { return fmt::format("{:.4f}", v); }

std::string KLabel(const Evaluation& ev) { return fmt::format("{:g}", ev.standard.coverage_factor); }

// Temperature min/mean/max per sensor, and the time span, as setup rows.
void AddMeasurementSetup(const measure::Measurement& m, std::vector<std::pair<std::string, std::string>>& rows,
                         const std::string& prefix) {
  for (const auto& [k, v] : m.metadata) rows.emplace_back(prefix + k, v);
  for (std::size_t s = 0; s < m.sensor_names.size(); ++s) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
    int n = 0;
    for (const auto& p : m.points)
      if (s < p.temperatures_c.size() && std::isfinite(p.temperatures_c[s])) {
        const double t = p.temperatures_c[s];
        lo = std::min(lo, t), hi = std::max(hi, t), sum += t, ++n;
      }
    if (n > 0)
      rows.emplace_back(prefix + "temperature " + m.sensor_names[s],
                        fmt::format("mean {:.2f} °C, range {:.2f} … {:.2f} °C ({} readings)", sum / n, lo, hi, n));
  }
  if (m.has_time) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& p : m.points)
      if (p.time_s) lo = std::min(lo, *p.time_s), hi = std::max(hi, *p.time_s);
    if (hi >= lo) rows.emplace_back(prefix + "duration", fmt::format("{:.0f} s", hi - lo));
  }
}

SvgChart DeviationChart(const measure::Measurement& m, const Evaluation& ev, const std::string& title) {
  SvgChartOptions o;
  o.title = title;
  o.x_label = "target position (mm)";
  o.y_label = "deviation (µm)";
  SvgChart chart(o);
  std::vector<double> x, up, dn, up_lo, up_hi, dn_lo, dn_hi;
  const double k = ev.standard.coverage_factor;
  for (const auto& t : ev.targets) {
    x.push_back(t.target_mm);
    up.push_back(t.mean_up_um), dn.push_back(t.mean_down_um);
    up_lo.push_back(t.mean_up_um - k * t.s_up_um), up_hi.push_back(t.mean_up_um + k * t.s_up_um);
    dn_lo.push_back(t.mean_down_um - k * t.s_down_um), dn_hi.push_back(t.mean_down_um + k * t.s_down_um);
  }
  const auto ks = KLabel(ev);
  chart.AddBand(fmt::format("forward ±{}s", ks), x, up_lo, up_hi, {.color = kUp});
  chart.AddBand(fmt::format("reverse ±{}s", ks), x, dn_lo, dn_hi, {.color = kDown});
  std::vector<double> px_up, py_up, px_dn, py_dn;
  for (const auto& p : m.points) {
    (p.direction == Direction::kForward ? px_up : px_dn).push_back(p.target_mm);
    (p.direction == Direction::kForward ? py_up : py_dn).push_back(p.deviation_um);
  }
  chart.AddPoints("", px_up, py_up, {.color = kUp, .marker_radius_px = 1.8});
  chart.AddPoints("", px_dn, py_dn, {.color = kDown, .marker_radius_px = 1.8});
  chart.AddLine("forward mean x̄↑", x, up, {.color = kUp, .width_px = 2.2, .markers = true});
  chart.AddLine("reverse mean x̄↓", x, dn, {.color = kDown, .width_px = 2.2, .markers = true});
  return chart;
}

void AddResultsTable(report::HtmlPage& page, const Evaluation& b, const Evaluation* a) {
  std::vector<std::string> header = {"quantity", "symbol", a ? "before (µm)" : "value (µm)"};
  if (a) header.insert(header.end(), {"after (µm)", "change (µm)"});
  HtmlTable t(header, "Axis results");
  struct Row {
    const char* what;
    const char* sym;
    double AxisResult::*field;
  };
  const Row rows[] = {
      {"bidirectional accuracy", "A", &AxisResult::A_um},
      {"unidirectional accuracy +", "A↑", &AxisResult::A_up_um},
      {"unidirectional accuracy −", "A↓", &AxisResult::A_down_um},
      {"reversal value (max |B_i|)", "B", &AxisResult::B_um},
      {"mean reversal value", "B̄", &AxisResult::B_mean_um},
      {"bidirectional systematic positioning error", "E", &AxisResult::E_um},
      {"unidirectional systematic error +", "E↑", &AxisResult::E_up_um},
      {"unidirectional systematic error −", "E↓", &AxisResult::E_down_um},
      {"mean bidirectional positioning error", "M", &AxisResult::M_um},
      {"bidirectional repeatability", "R", &AxisResult::R_um},
      {"unidirectional repeatability +", "R↑", &AxisResult::R_up_um},
      {"unidirectional repeatability −", "R↓", &AxisResult::R_down_um},
      {"VDI 3441 positional uncertainty", "P", &AxisResult::P_um},
      {"VDI 3441 position deviation", "Pa", &AxisResult::Pa_um},
      {"VDI 3441 max position scatter", "Ps max", &AxisResult::Ps_max_um},
      {"VDI 3441 mean position scatter", "Ps mean", &AxisResult::Ps_mean_um},
      {"VDI 3441 max reversal span", "U max", &AxisResult::U_max_um},
      {"VDI 3441 mean reversal span", "U mean", &AxisResult::U_mean_um},
  };
  for (const auto& r : rows) {
    std::vector<std::string> cells = {r.what, r.sym, Um(b.axis.*(r.field))};
    if (a) {
      cells.push_back(Um(a->axis.*(r.field)));
      cells.push_back(fmt::format("{:+.4f}", a->axis.*(r.field) - b.axis.*(r.field)));
    }
    t.AddRow(cells);
  }
  page.AddTable(t);
}

void AddPerTargetTable(report::HtmlPage& page, const Evaluation& ev, const std::string& caption) {
  const auto ks = KLabel(ev);
  HtmlTable t({"target (mm)", "n↑/n↓", "x̄↑ (µm)", "x̄↓ (µm)", "x̄ (µm)", "s↑ (µm)", "s↓ (µm)", "B_i (µm)",
               fmt::format("R↑ = {}s↑ (µm)", 2 * ev.standard.coverage_factor),
               fmt::format("R↓ = {}s↓ (µm)", 2 * ev.standard.coverage_factor), "R_i (µm)"},
              caption);
  (void)ks;
  for (const auto& r : ev.targets)
    t.AddRow({fmt::format("{:.4f}", r.target_mm), fmt::format("{}/{}", r.n_up, r.n_down), Um(r.mean_up_um),
              Um(r.mean_down_um), Um(r.mean_um), Um(r.s_up_um), Um(r.s_down_um), Um(r.reversal_um), Um(r.R_up_um),
              Um(r.R_down_um), Um(r.R_um)});
  page.AddTable(t);
}

void AddDecomposition(report::HtmlPage& page, const Evaluation& ev, const Decomposition& d) {
  page.AddHeading("Error decomposition (progressive, periodic, random)");
  page.AddParagraph(
      "Following the ball-screw error model δ = δ_f + δ_p + ψ: the progressive part δ_f is a low-order trend, the "
      "periodic part δ_p the harmonics of the screw lead, both fitted by least squares to the bidirectional mean "
      "deviations x̄_i; the random part ψ is the pooled run-to-run scatter σ, drawn as a ±" +
      fmt::format("{:g}", d.options.band_sigmas) + "σ band around the systematic curve.");
  std::vector<std::pair<std::string, std::string>> rows;
  rows.emplace_back("screw lead", d.options.lead_mm > 0 ? fmt::format("{:g} mm", d.options.lead_mm) : "not given");
  std::string trend;
  for (std::size_t i = 0; i < d.trend_coefficients.size(); ++i) {
    if (i == 0) trend += fmt::format("{:.4f} µm", d.trend_coefficients[0]);
    else if (i == 1) trend += fmt::format(", slope {:.4f} µm/m", d.trend_coefficients[1] * 1000);
    else trend += fmt::format(", c{} {:.4g} µm/mm^{}", i, d.trend_coefficients[i], i);
  }
  rows.emplace_back("progressive part (at " + fmt::format("{:g}", d.trend_origin_mm) + " mm)", trend);
  for (const auto& h : d.harmonics)
    rows.emplace_back(fmt::format("harmonic {} (period {:.4g} mm)", h.order, h.period_mm),
                      h.resolved ? fmt::format("amplitude {:.4f} µm, phase {:.2f} rad", h.amplitude_um, h.phase_rad)
                                 : "not fitted — " + h.note);
  rows.emplace_back("random part σ (pooled)", fmt::format("{:.4f} µm; ±{:g}σ = ±{:.4f} µm", d.sigma_um,
                                                           d.options.band_sigmas, d.options.band_sigmas * d.sigma_um));
  rows.emplace_back("unexplained systematic RMS", fmt::format("{:.4f} µm", d.residual_rms_um));
  rows.emplace_back("target spacing", fmt::format("{:.4g} … {:.4g} mm", d.min_gap_mm, d.max_gap_mm));
  page.AddKeyValueTable(rows, "Decomposition");
  for (const auto& n : d.notes) page.AddNote("Note: " + n);

  SvgChartOptions o;
  o.title = "Decomposition of the mean bidirectional deviation";
  o.x_label = "target position (mm)";
  o.y_label = "deviation (µm)";
  SvgChart chart(o);
  // Dense curves: the periodic part is only drawn between targets when it was resolved.
  const double x0 = ev.targets.front().target_mm, x1 = ev.targets.back().target_mm;
  std::vector<double> xs;
  if (d.periodic_fitted()) {
    const int n = 600;
    for (int i = 0; i <= n; ++i) xs.push_back(x0 + (x1 - x0) * i / n);
  } else {
    for (const auto& t : ev.targets) xs.push_back(t.target_mm);
  }
  std::vector<double> sys, lo, hi, prog;
  const double half = d.options.band_sigmas * d.sigma_um;
  for (double x : xs) {
    sys.push_back(d.Systematic(x));
    prog.push_back(d.Progressive(x));
    lo.push_back(sys.back() - half);
    hi.push_back(sys.back() + half);
  }
  chart.AddBand(fmt::format("random ±{:g}σ", d.options.band_sigmas), xs, lo, hi, {.color = "#009E73"});
  chart.AddLine("progressive δ_f", xs, prog, {.color = "#555555", .dashed = true});
  if (d.periodic_fitted()) chart.AddLine("progressive + periodic", xs, sys, {.color = "#CC79A7", .width_px = 2});
  std::vector<double> tx, ty;
  for (const auto& p : d.points) tx.push_back(p.target_mm), ty.push_back(p.mean_um);
  chart.AddPoints("mean x̄_i", tx, ty, {.color = "#000000", .marker_radius_px = 3.5});
  page.AddChart(chart);

  SvgChartOptions o2 = o;
  o2.title = "Periodic part and unexplained residual";
  SvgChart parts(o2);
  std::vector<double> per, res;
  for (const auto& p : d.points) per.push_back(p.periodic_um), res.push_back(p.residual_um);
  if (d.periodic_fitted()) {
    std::vector<double> dense;
    for (double x : xs) dense.push_back(d.Periodic(x));
    parts.AddLine("periodic δ_p", xs, dense, {.color = "#CC79A7", .width_px = 2});
  }
  parts.AddLine("residual x̄_i − δ_f − δ_p", tx, res, {.color = "#E69F00", .markers = true});
  parts.AddHorizontalLine(fmt::format("+{:g}σ", d.options.band_sigmas), half, {.color = "#009E73", .dashed = true});
  parts.AddHorizontalLine(fmt::format("−{:g}σ", d.options.band_sigmas), -half, {.color = "#009E73", .dashed = true});
  page.AddChart(parts);
}

}  // namespace

report::HtmlPage BuildAnalysisReport(const AnalysisReportInput& in) {
  if (!in.before.measurement || !in.before.evaluation)
    throw std::invalid_argument("BuildAnalysisReport: the 'before' measurement and evaluation are required");
  const auto& m = *in.before.measurement;
  const auto& ev = *in.before.evaluation;
  const Evaluation* after = in.after ? in.after->evaluation : nullptr;
  const measure::Measurement* after_m = in.after ? in.after->measurement : nullptr;
  if (in.after && (!after || !after_m))
    throw std::invalid_argument("BuildAnalysisReport: 'after' needs both measurement and evaluation");

  const auto axis = m.Meta("axis");
  report::HtmlPage page(fmt::format("Positioning test{} — {}", axis ? " of axis " + *axis : "", ev.standard.name));

  page.AddHeading("Setup");
  std::vector<std::pair<std::string, std::string>> rows;
  rows.emplace_back("file", m.source);
  rows.emplace_back("standard", ev.standard.name + (ev.standard.requested_as.empty() ||
                                                            ev.standard.requested_as == ev.standard.name
                                                        ? ""
                                                        : " (requested as " + ev.standard.requested_as + ")"));
  rows.emplace_back("coverage factor k", KLabel(ev));
  rows.emplace_back("targets", fmt::format("{} from {:g} to {:g} mm", ev.targets.size(), ev.targets.front().target_mm,
                                           ev.targets.back().target_mm));
  rows.emplace_back("runs", fmt::format("{} per direction", ev.runs));
  AddMeasurementSetup(m, rows, "");
  if (after) {
    rows.emplace_back("after: file", after_m->source);
    rows.emplace_back("after: targets × runs", fmt::format("{} × {}", after->targets.size(), after->runs));
    AddMeasurementSetup(*after_m, rows, "after: ");
  }
  page.AddKeyValueTable(rows);
  page.AddNote("Deviation = actual − target (µm). Forward (↑, +) = approach towards increasing coordinate. "
               "Formulas: ISO 230-2 (k = " + KLabel(ev) + ") and VDI/DGQ 3441; see docs/analysis.md.");

  page.AddHeading("Results");
  page.AddParagraph(fmt::format("A = {} µm, B = {} µm, E = {} µm, M = {} µm, R = {} µm{}", Um(ev.axis.A_um),
                                Um(ev.axis.B_um), Um(ev.axis.E_um), Um(ev.axis.M_um), Um(ev.axis.R_um),
                                after ? fmt::format("; after: A = {} µm, E = {} µm, R = {} µm", Um(after->axis.A_um),
                                                    Um(after->axis.E_um), Um(after->axis.R_um))
                                      : ""));
  AddResultsTable(page, ev, after);

  page.AddHeading("Mean positioning deviation");
  page.AddChart(DeviationChart(m, ev, after ? "Before: forward and reverse mean deviation"
                                            : "Forward and reverse mean deviation"));
  if (after) {
    page.AddChart(DeviationChart(*after_m, *after, "After: forward and reverse mean deviation"));
    SvgChartOptions o;
    o.title = "Before vs after (mean deviations)";
    o.x_label = "target position (mm)";
    o.y_label = "deviation (µm)";
    SvgChart both(o);
    auto add = [&](const Evaluation& e, const char* tag, bool dashed) {
      std::vector<double> x, up, dn;
      for (const auto& t : e.targets) x.push_back(t.target_mm), up.push_back(t.mean_up_um), dn.push_back(t.mean_down_um);
      both.AddLine(std::string(tag) + " x̄↑", x, up, {.color = kUp, .dashed = dashed, .markers = true});
      both.AddLine(std::string(tag) + " x̄↓", x, dn, {.color = kDown, .dashed = dashed, .markers = true});
    };
    add(ev, "before", true);
    add(*after, "after", false);
    page.AddChart(both);
  }

  {
    SvgChartOptions o;
    o.title = "Repeatability and reversal per target";
    o.x_label = "target position (mm)";
    o.y_label = "µm";
    SvgChart chart(o);
    std::vector<double> x, ru, rd, ri, bi;
    for (const auto& t : ev.targets)
      x.push_back(t.target_mm), ru.push_back(t.R_up_um), rd.push_back(t.R_down_um), ri.push_back(t.R_um),
          bi.push_back(t.reversal_um);
    chart.AddLine("R_i↑", x, ru, {.color = kUp, .markers = true});
    chart.AddLine("R_i↓", x, rd, {.color = kDown, .markers = true});
    chart.AddLine("R_i (bidirectional)", x, ri, {.color = "#000000", .width_px = 2.2, .markers = true});
    chart.AddLine("B_i (reversal)", x, bi, {.color = "#009E73", .dashed = true, .markers = true});
    page.AddChart(chart);
  }

  if (in.decomposition) AddDecomposition(page, ev, *in.decomposition);

  page.AddHeading("Per-target values");
  AddPerTargetTable(page, ev, after ? "Before" : "Per target");
  if (after) AddPerTargetTable(page, *after, "After");
  return page;
}

}  // namespace trueaxis::analysis
