#include "demo_report.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/duration_text.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/report/html_page.hpp"
#include "trueaxis/report/svg_chart.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/sim/ambient_profile.hpp"

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

// µm to 0.1: the laser's repeatability is a few µm.
std::string Um(double v) { return F(v, 1); }

std::string Verdict(const StateResult& s) {
  return s.AtGoal() ? "goal" : s.UnderMustLine() ? "must" : "MISSED";
}

// A wall time per cycle: µs below a millisecond, ms above.
std::string CycleTime(double s) { return s < 1e-3 ? fmt::format("{:.1f} µs", s * 1e6) : fmt::format("{:.1f} ms", s * 1e3); }

// "2026-04-01T07:00:59" → "2026-04-01 07:00".
std::string ShortDate(const std::string& iso) {
  return iso.size() >= 16 && iso[10] == 'T' ? iso.substr(0, 10) + " " + iso.substr(11, 5) : iso;
}

std::string Range(double lo, double hi, int digits) {
  return F(lo, digits) == F(hi, digits) ? F(lo, digits) : F(lo, digits) + "–" + F(hi, digits);
}

std::string Count(std::size_t n, std::size_t of) { return fmt::format("{} of {}", n, of); }

// The first screen: what was achieved per axis, the verdict, and anything that needs attention.
void WriteSummary(report::HtmlPage& page, const DemoResult& r) {
  page.AddParagraph(fmt::format(
      "A calibration campaign on the virtual machine, an automatic fit of the composite model per axis and direction, "
      "then a working day and another day in another season on another run of the same machine ({}, simulated), "
      "with the compensator in its loop every cycle. At each state every axis was measured by the laser with "
      "compensation on and off (ISO 230-2, k = 2); none of these tests was used in the fit.",
      r.DaySpans()));
  page.AddHeading("What compensation achieved");
  report::HtmlTable t({"axis", "tests", "A off (µm)", "A on (µm)", "A off / A on", "under the must line", "at the goal"},
                      "Bidirectional positioning accuracy A per axis over the held-out states: the range from the "
                      "best to the worst state.");
  std::vector<std::string> axes;
  for (const auto& s : r.states)
    if (std::find(axes.begin(), axes.end(), s.axis) == axes.end()) axes.push_back(s.axis);
  std::size_t must = 0, goal = 0;
  for (const auto& axis : axes) {
    double off_lo = 1e300, off_hi = -1e300, on_lo = 1e300, on_hi = -1e300, f_lo = 1e300, f_hi = -1e300;
    std::size_t n = 0, axis_must = 0, axis_goal = 0;
    for (const auto& s : r.states) {
      if (s.axis != axis) continue;
      ++n;
      off_lo = std::min(off_lo, s.eval_off.axis.A_um), off_hi = std::max(off_hi, s.eval_off.axis.A_um);
      on_lo = std::min(on_lo, s.eval_on.axis.A_um), on_hi = std::max(on_hi, s.eval_on.axis.A_um);
      f_lo = std::min(f_lo, s.Factor()), f_hi = std::max(f_hi, s.Factor());
      axis_must += s.UnderMustLine();
      axis_goal += s.AtGoal();
    }
    must += axis_must;
    goal += axis_goal;
    t.AddRow({axis, std::to_string(n), Range(off_lo, off_hi, 1), Range(on_lo, on_hi, 1), Range(f_lo, f_hi, 1) + "×",
              Count(axis_must, n), Count(axis_goal, n)});
  }
  page.AddTable(t);
  const std::size_t n = r.states.size();
  page.AddParagraph(fmt::format("Verdict: {} — {} of {} tests under the must line, {} at the goal.",
                                must == n ? "PASSED" : "NOT PASSED", must, n, goal));
  page.AddNote("Must line: A_on ≤ max(20 % of A_off, 2 × R_on), compensation made the axis better and did not "
               "scatter it (R_on ≤ 2 × R_off + 2 µm). Goal: A_on ≤ max(10 % of A_off, 1.3 × R_on). R is the "
               "repeatability; the marks of the machine-zoo benchmark (docs/concepts.md).");
  // What needs attention, in one line each (details further down).
  std::uint64_t saturated = 0;
  for (auto c : r.clamped_cycles) saturated += c;
  std::string alarms;
  for (const auto& a : r.alarm_summary)
    alarms += fmt::format("{}{} ({}×, {} in all)", alarms.empty() ? "" : ", ", a.alarm, a.times, FormatDuration(a.total_s));
  page.AddNote(fmt::format("{} Alarms: {}.", saturated ? fmt::format("The correction saturated in {} axis-cycles.", saturated)
                                                       : "No axis saturated.",
                           alarms.empty() ? "none" : alarms));
}

void WriteDay(report::HtmlPage& page, const DemoResult& r) {
  page.AddHeading("The day: temperatures and corrections");
  if (r.day.empty()) return;
  report::SvgChartOptions to;
  to.title = "temperatures (as the compensator used them)";
  to.x_label = "time since 07:00 of the working day (h); the other day follows after a gap";
  to.y_label = "°C";
  to.y_includes_zero = false;
  report::SvgChart tc(to);
  for (std::size_t c = 0; c < r.channel_names.size(); ++c) {
    std::vector<double> x, y;
    for (std::size_t i = 0; i < r.day.size(); ++i) {
      const auto& d = r.day[i];
      if (i > 0 && d.other_day && !r.day[i - 1].other_day) {
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

// Saturation is never silent: each axis's bound, and how often the model asked for more.
void WriteBounds(report::HtmlPage& page, const DemoResult& r) {
  page.AddHeading("Compensation bounds and saturation");
  report::HtmlTable bt({"axis", "bound (µm)", "how it was set", "cycles saturated", "share of the day",
                        "cycles beyond the fitted envelope", "cycles with the room outside the fitted range"});
  for (std::size_t i = 0; i < r.machine_axes.size() && i < r.bound_um.size(); ++i) {
    const std::uint64_t n = i < r.clamped_cycles.size() ? r.clamped_cycles[i] : 0;
    bt.AddRow({r.machine_axes[i], fmt::format("±{:.0f}", r.bound_um[i]),
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
}

// Alarms summarised (what, how often, how long, when); the raw log of changes folded away.
void WriteAlarms(report::HtmlPage& page, const DemoResult& r) {
  page.AddHeading("Alarms");
  if (r.alarm_summary.empty()) {
    page.AddNote("No alarm was raised on either day.");
    return;
  }
  report::HtmlTable at({"alarm", "times raised", "active in all", "first raised", "last raised", "last cleared"},
                       "Each alarm of the compensator on the two days (machine clock); an alarm still active when "
                       "the machine was switched off counts until then.");
  for (const auto& a : r.alarm_summary)
    at.AddRow({a.alarm, std::to_string(a.times), FormatDuration(a.total_s), sim::FormatIsoTime(a.first_raised_s),
               sim::FormatIsoTime(a.last_raised_s),
               std::isnan(a.last_cleared_s) ? "still active" : sim::FormatIsoTime(a.last_cleared_s)});
  page.AddTable(at);
  if (r.alarm_log.empty()) return;
  page.BeginDetails(fmt::format("the alarm log: {} change{} of the alarm state{}", r.alarm_changes,
                                r.alarm_changes == 1 ? "" : "s",
                                r.alarm_changes > r.alarm_log.size() ? fmt::format(" (the first {})", r.alarm_log.size()) : ""));
  std::string log;
  for (const auto& line : r.alarm_log) log += line + "\n";
  page.AddRawHtml("<pre>" + report::EscapeHtml(log) + "</pre>\n");
  page.EndDetails();
}

void WriteLoop(report::HtmlPage& page, const DemoResult& r) {
  page.AddHeading("Compensator loop");
  const auto& st = r.loop_stats;
  page.AddKeyValueTable({
      {"days (simulated)", r.DaySpans()},
      {"compensated", fmt::format("{} of machine time, {} cycles of {:.0f} ms", FormatDuration(r.compensated_s),
                                  st.cycles, r.period_s * 1000)},
      {"cycle cost (wall time per cycle)",
       fmt::format("p50 {}, p99 {}, max {} (cycle {} of {})", CycleTime(st.p50_cycle_s), CycleTime(st.p99_cycle_s),
                   CycleTime(st.max_cycle_s), st.max_cycle_number, st.cycles)},
      {"cycles longer than the period",
       fmt::format("{} ({:.4f} % of the cycles)", st.long_cycles,
                   st.cycles ? 100.0 * static_cast<double>(st.long_cycles) / static_cast<double>(st.cycles) : 0.0)},
  });
  page.AddNote(fmt::format(
      "The days run in simulated time: each cycle is computed as fast as this computer allows, with no deadline to "
      "miss, so no overrun is counted here. An overrun is a cycle that ends after the next deadline ({:.0f} ms after "
      "its start) in the real-time loop of `trueaxis run`, which counts them. The cost is the wall time of one cycle — "
      "the compensator's step, its reads and writes of the virtual machine and the day's recording — on this "
      "computer while other programs ran: a maximum far above p99 is a cycle the operating system interrupted (or "
      "the first, with nothing yet in the caches), not the compensator's work. p99 is what a real-time period must "
      "hold; the cycles longer than the period are those that would have overrun.",
      r.period_s * 1000));
}

void WriteModel(report::HtmlPage& page, const DemoResult& r, const model::FitResult& fit) {
  page.AddHeading("Model");
  report::HtmlTable mt({"axis", "Px (mm)", "ρ (µm/m/°C)", "key sensors", "Er(x) ↑ / ↓", "thermal CV RMS (µm)",
                        "CV RMS without thermal term (µm)"});
  // What Er(x) is per direction: a table says its points, a polynomial its degree.
  auto er_kind = [](const model::DirectionFitStats& d) {
    return d.kind == model::GeometricError::Kind::kTable ? fmt::format("table of {} points", d.targets)
                                                         : fmt::format("polynomial, degree {}", d.degree.degree);
  };
  for (const auto& a : fit.summary.axes)
    mt.AddRow({a.axis, F(a.reference_position_mm, 1), F(a.rho_um_per_mm_per_c * 1000, 2),
               a.key_sensors.empty() ? "(none)" : fmt::format("{}", fmt::join(a.key_sensors, ", ")),
               fmt::format("{} / {}", er_kind(a.directions[0]), er_kind(a.directions[1])),
               F(a.thermal_cv_rms_um), F(a.no_thermal_cv_rms_um)});
  page.AddTable(mt);
  page.AddNote("CV RMS: the leave-one-state-out cross-validated residual (each state predicted by a model fitted "
               "without it), to 0.01 µm: an average over every target and run of a state.");
  // The fallback models, for a lost sensor: one row each.
  report::HtmlTable ft({"axis", "without", "how its keys were found", "key sensors", "room term", "CV RMS (µm)",
                        "the full model's (µm)", "kept"},
                       "Fallback models: fitted without one sensor each, for the compensator when that sensor is "
                       "lost (the best by CV are kept).");
  for (const auto& a : fit.summary.axes)
    for (const auto& f : a.fallbacks)
      ft.AddRow({a.axis,
                 f.partners.empty() ? f.without : fmt::format("{} (and {})", f.without, fmt::join(f.partners, ", ")),
                 f.how, fmt::format("{}", fmt::join(f.key_sensors, ", ")), f.room_term ? "yes" : "no",
                 F(f.cv_rms_um), F(a.thermal_cv_rms_um), f.kept ? "yes" : "no"});
  if (ft.row_count() > 0) page.AddTable(ft);
  page.BeginDetails("the fit's own summary (text)");
  page.AddRawHtml("<pre>" + report::EscapeHtml(r.fit_brief) + "</pre>\n");
  page.EndDetails();
  page.AddNote(fmt::format("model file {} (sha256 {})", r.model_path, model::Sha256OfFile(r.model_path)));
}

}  // namespace

void WriteDemoReport(const DemoResult& r, const DemoOptions& o, const model::FitResult& fit,
                     const sim::MachineDescription& md) {
  report::HtmlPage page(fmt::format("trueaxis demo — {}: geometric + thermal compensation in the loop", md.name));
  WriteSummary(page, r);

  page.AddHeading("Positioning accuracy per state");
  report::HtmlTable t({"state", "axis", "date (simulated)", "air (°C)", "nut rise (°C)", "A off (µm)", "A on (µm)",
                       "A off / A on", "E off (µm)", "E on (µm)", "B off (µm)", "B on (µm)", "R on (µm)", "verdict"},
                      "A: bidirectional positioning accuracy; E: systematic deviation; B: reversal value; R: "
                      "repeatability (ISO 230-2). Nut rise: the axis' nut sensor against the day's cold test. "
                      "Verdict: at the goal, under the must line only, or MISSED (see above).");
  for (const auto& s : r.states)
    t.AddRow({s.state, s.axis, ShortDate(s.date), F(s.ambient_c, 1), F(s.nut_rise_c, 1), Um(s.eval_off.axis.A_um),
              Um(s.eval_on.axis.A_um), F(s.Factor(), 1) + "×", Um(s.eval_off.axis.E_um), Um(s.eval_on.axis.E_um),
              Um(s.eval_off.axis.B_um), Um(s.eval_on.axis.B_um), Um(s.eval_on.axis.R_um), Verdict(s)});
  page.AddTable(t);
  page.AddNote("The compensated test ran first, the uncompensated one right after it: the machine cools a little "
               "meanwhile, so the uncompensated figure is, if anything, flattered. Figures to 0.1 µm: the laser's "
               "repeatability R is 2–4 µm, finer digits would be noise.");

  // The error curves, one section per axis: the state with the largest error in view, the others folded.
  page.AddHeading("Error curves");
  std::vector<std::string> axes;
  for (const auto& s : r.states)
    if (std::find(axes.begin(), axes.end(), s.axis) == axes.end()) axes.push_back(s.axis);
  for (const auto& axis : axes) {
    const StateResult* worst = nullptr;
    for (const auto& s : r.states)
      if (s.axis == axis && (!worst || s.eval_off.axis.A_um > worst->eval_off.axis.A_um)) worst = &s;
    page.AddHeading(fmt::format("Axis {}", axis), 3);
    page.AddChart(ErrorCurves(*worst));
    std::vector<const StateResult*> others;
    for (const auto& s : r.states)
      if (s.axis == axis && &s != worst) others.push_back(&s);
    if (others.empty()) continue;
    page.BeginDetails(fmt::format("axis {}: the other {} state{}", axis, others.size(), others.size() == 1 ? "" : "s"));
    for (const auto* s : others) page.AddChart(ErrorCurves(*s));
    page.EndDetails();
  }

  WriteDay(page, r);
  WriteBounds(page, r);
  WriteAlarms(page, r);
  WriteLoop(page, r);
  WriteModel(page, r, fit);

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
      {"history database", r.history_path},
      {"measurement files", (std::string(r.out_dir) + "/day/*.csv")},
  });
  page.Save(r.report_path);
}

}  // namespace trueaxis::demo
