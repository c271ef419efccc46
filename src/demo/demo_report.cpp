#include "demo_report.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/model/sha256.hpp"
#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::demo {
namespace {

std::string F(double v, int digits = 2) { return std::isfinite(v) ? fmt::format("{:.{}f}", v, digits) : "—"; }

report::SvgChart ErrorCurves(const StateResult& r) {
  report::SvgChartOptions co;
  co.title = fmt::format("{} axis, {} ({}): mean deviation per target", r.axis, r.state, r.date);
  co.x_label = "target position (mm)";
  co.y_label = "deviation = actual − target (µm)";
  report::SvgChart chart(co);
  auto series = [](const analysis::Evaluation& e, bool up, int band) {
    std::vector<double> x, y, lo, hi;
    for (const auto& t : e.targets) {
      const double m = up ? t.mean_up_um : t.mean_down_um;
      const double s = up ? t.s_up_um : t.s_down_um;
      x.push_back(t.target_mm);
      y.push_back(m);
      lo.push_back(m - band * s);
      hi.push_back(m + band * s);
    }
    return std::make_tuple(x, y, lo, hi);
  };
  // Every series with its ±2s band (the spread of the runs), bands first so the lines sit on top.
  struct Curve {
    const analysis::Evaluation* eval;
    bool up;
    const char* label;
    const char* color;
    bool dashed;
  };
  const Curve curves[] = {{&r.eval_off, true, "uncompensated ↑ (forward)", "#c0392b", false},
                          {&r.eval_off, false, "uncompensated ↓ (reverse)", "#e67e22", true},
                          {&r.eval_on, true, "compensated ↑ (forward)", "#1f6fb2", false},
                          {&r.eval_on, false, "compensated ↓ (reverse)", "#16a085", true}};
  for (const auto& c : curves) {
    auto [x, y, lo, hi] = series(*c.eval, c.up, 2);
    report::SeriesStyle band{c.color};
    band.fill_opacity = 0.12;
    chart.AddBand(fmt::format("{} ±2s", c.label), x, lo, hi, band);
  }
  for (const auto& c : curves) {
    auto [x, y, lo, hi] = series(*c.eval, c.up, 2);
    report::SeriesStyle line{c.color};
    line.dashed = c.dashed;
    chart.AddLine(c.label, x, y, line);
  }
  return chart;
}

}  // namespace

void WriteDemoReport(const DemoResult& r, const DemoOptions& o, const model::FitResult& fit,
                     const sim::MachineDescription& md) {
  report::HtmlPage page(fmt::format("trueaxis demo — {}: geometric + thermal compensation in the loop", md.name));
  page.AddParagraph(
      "A calibration campaign with the virtual laser interferometer, an automatic fit of the composite model "
      "Er(x,T) = Er(x) + tanβ·(Px − P0) + ρ·ΔT_env·(Px − P0) per axis and direction, then a simulated "
      "working day on another run of the same machine — cold start, machining, coolant on and off, the workshop's "
      "air drifting — and another day in another season, with the real-time compensator running every cycle through "
      "the machine's CNC and temperature interfaces. At each state every axis was measured twice by the laser, with "
      "compensation on and then off, and evaluated by ISO 230-2:2014 (k = 2). None of the day's measurements was used "
      "in the fit.");

  page.AddHeading("Positioning accuracy before and after compensation");
  report::HtmlTable t({"state", "axis", "date (simulated)", "air (°C)", "nut rise (°C)", "A off (µm)", "A on (µm)",
                       "A off / A on", "E off (µm)", "E on (µm)", "B off (µm)", "B on (µm)", "R on (µm)"},
                      "A: bidirectional positioning accuracy; E: systematic deviation; B: reversal value; R: "
                      "repeatability (ISO 230-2). Nut rise: the axis' nut sensor against the day's cold test.");
  for (const auto& s : r.states)
    t.AddRow({s.state, s.axis, s.date, F(s.ambient_c, 1), F(s.nut_rise_c, 2), F(s.eval_off.axis.A_um),
              F(s.eval_on.axis.A_um), F(s.Factor(), 1) + "×", F(s.eval_off.axis.E_um), F(s.eval_on.axis.E_um),
              F(s.eval_off.axis.B_um), F(s.eval_on.axis.B_um), F(s.eval_on.axis.R_um)});
  page.AddTable(t);
  page.AddNote("The compensated test ran first, the uncompensated one right after it: the machine cools a little "
               "meanwhile, so the uncompensated figure is, if anything, flattered.");

  // Saturation is never silent: each axis's bound, and how often the model asked for more.
  page.AddHeading("Compensation bounds and saturation");
  report::HtmlTable bt({"axis", "bound (µm)", "how it was set", "cycles saturated", "share of the day",
                        "cycles beyond the fitted envelope", "cycles with the room outside the fitted range"});
  for (std::size_t i = 0; i < r.machine_axes.size() && i < r.bound_um.size(); ++i) {
    const std::uint64_t n = i < r.clamped_cycles.size() ? r.clamped_cycles[i] : 0;
    bt.AddRow({r.machine_axes[i], fmt::format("±{:g}", r.bound_um[i]),
               i < r.bound_source.size() ? r.bound_source[i] : "", std::to_string(n),
               r.day_cycles ? fmt::format("{:.3f} %", 100.0 * static_cast<double>(n) / static_cast<double>(r.day_cycles))
                            : "-",
               std::to_string(i < r.extrapolated_cycles.size() ? r.extrapolated_cycles[i] : 0),
               std::to_string(i < r.room_extrapolated_cycles.size() ? r.room_extrapolated_cycles[i] : 0)});
  }
  page.AddTable(bt);
  std::uint64_t saturated = 0;
  for (auto n : r.clamped_cycles) saturated += n;
  page.AddNote(saturated ? fmt::format("WARNING: the correction saturated at its bound in {} axis-cycles "
                                       "(alarm correction_clamped): the figures above include that.", saturated)
                         : "No axis saturated: every correction the model asked for was applied within its bound.");
  std::uint64_t extrapolated = 0;
  for (auto n : r.extrapolated_cycles) extrapolated += n;
  if (extrapolated)
    page.AddNote(fmt::format("WARNING: in {} axis-cycles the temperatures lay beyond the model's fitted envelope "
                             "(alarm model_extrapolated): its thermal slope was held at the envelope's edge "
                             "instead of extrapolated (docs/model-file.md).", extrapolated));
  std::uint64_t room = 0;
  for (auto n : r.room_extrapolated_cycles) room += n;
  if (room)
    page.AddNote(fmt::format("WARNING: in {} axis-cycles the room temperature lay outside the range the model was "
                             "fitted on (alarm model_extrapolated): its room term was extrapolated. Calibrate "
                             "with the room that cold or warm too (docs/campaign.md, --ambient-hours and "
                             "--ambient-days).", room));

  for (const auto& f : r.sensor_faults) page.AddNote("Sensor fault in the working day: " + f + ".");
  for (std::size_t i = 0; i < r.machine_axes.size(); ++i) {
    const std::uint64_t reduced = i < r.fallback_model_cycles.size() ? r.fallback_model_cycles[i] : 0;
    const std::uint64_t averaged = i < r.averaged_fallback_cycles.size() ? r.averaged_fallback_cycles[i] : 0;
    const std::uint64_t lost = i < r.sensor_fallback_cycles.size() ? r.sensor_fallback_cycles[i] : 0;
    if (reduced || lost)
      page.AddNote(fmt::format("WARNING: axis {} lost a sensor of its model (alarm sensor_fallback): {} cycles on a "
                               "fallback model fitted without it ({} of them the mean of the fallbacks replacing "
                               "that sensor), {} cycles without the thermal part (docs/runtime.md, sensor faults).",
                               r.machine_axes[i], reduced, averaged, lost));
  }

  page.AddHeading("Setup");
  const auto& so = o.compensator.shaper;
  page.AddKeyValueTable({
      {"machine", fmt::format("{} ({})", md.name, o.machine_file)},
      {"axes", fmt::format("{}", fmt::join(r.axes, ", "))},
      {"temperature channels", fmt::format("{}", fmt::join(r.channel_names, ", "))},
      {"campaign", fmt::format("{} (run seed {})", r.campaign_dir, o.seed)},
      {"working day", fmt::format("run seed {}, {} days after the campaign start; another day at +{} days", o.seed + 1000,
                                  o.day_offset, o.other_day_offset)},
      {"compensation cycle", fmt::format("{:.0f} ms of machine time (simulated-time loop)", o.period_s * 1000)},
      {"interface", r.interface_used},
      {"output limits", fmt::format("|correction| ≤ the axis's bound (table above), change ≤ {} µm per cycle, "
                                    "quantum δ = 1 µm, hysteresis {} δ", so.max_step_um, so.hysteresis)},
      {"sensor fault policy", fmt::format("hold last good {} s, then the model's fallback without the lost key sensor (starting from the model's last correction, the difference decaying over {} s), else the geometric part only", o.compensator.sensor.hold_last_good_s, o.compensator.sensor.fallback_handover_s)},
      {"mode", o.fast ? "--fast (fewer targets and runs)" : "full"},
      {"wall time", fmt::format("{:.1f} s (campaign {:.1f} s, fit {:.1f} s, day {:.1f} s)", r.wall_s, r.campaign_wall_s,
                                r.fit_wall_s, r.day_wall_s)},
  });

  page.AddHeading("Model");
  report::HtmlTable mt({"axis", "Px (mm)", "ρ (µm/mm/°C)", "key sensors", "Er(x) ↑ / ↓", "thermal CV RMS (µm)",
                        "CV RMS without thermal term (µm)"});
  // What Er(x) is per direction: a table says its points, a polynomial its degree.
  auto er_kind = [](const model::DirectionFitStats& d) {
    return d.kind == model::GeometricError::Kind::kTable ? fmt::format("table of {} points", d.targets)
                                                         : fmt::format("polynomial, degree {}", d.degree.degree);
  };
  for (const auto& a : fit.summary.axes)
    mt.AddRow({a.axis, F(a.reference_position_mm, 1), F(a.rho_um_per_mm_per_c, 5),
               a.key_sensors.empty() ? "(none)" : fmt::format("{}", fmt::join(a.key_sensors, ", ")),
               fmt::format("{} / {}", er_kind(a.directions[0]), er_kind(a.directions[1])),
               F(a.thermal_cv_rms_um), F(a.no_thermal_cv_rms_um)});
  page.AddTable(mt);
  page.AddRawHtml("<pre>" + report::EscapeHtml(r.fit_brief) + "</pre>");
  page.AddNote(fmt::format("model file {} (sha256 {})", r.model_path, model::Sha256OfFile(r.model_path)));

  page.AddHeading("Error curves");
  for (const auto& s : r.states) page.AddChart(ErrorCurves(s));

  page.AddHeading("The day: temperatures and corrections");
  if (!r.day.empty()) {
    report::SvgChartOptions to;
    to.title = "temperatures (as the compensator used them)";
    to.x_label = "time since 07:00 of the working day (h); the other day follows after a gap";
    to.y_label = "°C";
    to.y_includes_zero = false;
    report::SvgChart tc(to);
    for (std::size_t c = 0; c < r.channel_names.size(); ++c) {
      std::vector<double> x, y;
      for (const auto& d : r.day) {
        if (!x.empty() && d.other_day && !r.day[&d - &r.day[0] - 1].other_day) {
          x.push_back(std::nan(""));
          y.push_back(std::nan(""));
        }
        x.push_back(d.time_h);
        y.push_back(c < d.temp_c.size() ? d.temp_c[c] : std::nan(""));
      }
      tc.AddLine(r.channel_names[c], x, y);
    }
    page.AddChart(tc);
    report::SvgChartOptions ko;
    ko.title = "correction written to the CNC (µm); coolant state";
    ko.x_label = to.x_label;
    ko.y_label = "correction (µm)";
    report::SvgChart kc(ko);
    for (std::size_t a = 0; a < r.machine_axes.size(); ++a) {
      std::vector<double> x, y;
      for (const auto& d : r.day) {
        x.push_back(d.time_h);
        y.push_back(a < d.correction_um.size() ? d.correction_um[a] : std::nan(""));
      }
      kc.AddLine("axis " + r.machine_axes[a], x, y);
    }
    std::vector<double> x, y;
    for (const auto& d : r.day) {
      x.push_back(d.time_h);
      y.push_back(d.coolant == CoolantState::kOff ? 0.0 : 5.0);
    }
    kc.AddLine("coolant on (5) / off (0)", x, y, report::SeriesStyle{"#888888", 1.0, true});
    page.AddChart(kc);
    page.AddNote("Between the tests the axes machine (reciprocating at 3000/4000 mm/min, 70 % duty); during a test "
                 "only the measured axis moves. With compensation off the correction is ramped to 0 first.");
  }

  page.AddHeading("Compensator loop");
  page.AddKeyValueTable({
      {"cycles", fmt::format("{}", r.loop_stats.cycles)},
      {"machine time", fmt::format("{:.1f} h", r.machine_time_h)},
      {"cycle cost (compensator only)", fmt::format("mean {:.2f} µs, max {:.1f} µs", r.loop_stats.mean_cycle_s * 1e6,
                                                    r.loop_stats.max_cycle_s * 1e6)},
      {"alarms seen", r.alarms_seen ? runtime::AlarmNames(r.alarms_seen) : "none"},
      {"alarm log", r.alarm_log.empty() ? "(empty)" : fmt::format("{}", fmt::join(r.alarm_log, "; "))},
      {"history database", r.history_path},
      {"measurement files", (std::string(r.out_dir) + "/day/*.csv")},
  });
  page.Save(r.report_path);
}

}  // namespace trueaxis::demo
