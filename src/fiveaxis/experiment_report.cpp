// Five-axis experiment report (HTML, report/ builders).
#include "trueaxis/fiveaxis/experiment_report.hpp"

#include <cmath>

#include <fmt/format.h>

namespace trueaxis::fiveaxis {
namespace {

// Every k-th sample so a chart holds at most ~2000 points.
template <typename F>
std::vector<double> Thin(std::size_t n, F value) {
  const std::size_t step = std::max<std::size_t>(1, n / 2000);
  std::vector<double> out;
  for (std::size_t i = 0; i < n; i += step) out.push_back(value(i));
  return out;
}

}  // namespace

double ReductionPercent(double before, double after) { return before > 0 ? 100.0 * (1.0 - after / before) : 0.0; }

report::HtmlPage BuildExperimentReport(const Experiment& x, const FiveAxisMachine& m, const TrackingErrorModel& model) {
  const auto names = m.axis_names();
  report::HtmlPage page("Five-axis contour error — " + x.path.name);
  page.AddParagraph(
      "Seed 004: servo tracking errors of the five drives, predicted by a model identified from axis sine tests, "
      "reduced by the averaged velocity feed-forward and then by correcting the axis commands through the kinematics. "
      "Contour error = distance of the actual tool tip (forward kinematics of the actual joints) from the nearest "
      "point of the programmed path; orientation error = angle of the actual tool axis from the programmed one there.");
  page.AddKeyValueTable({{"machine", m.name + " (" + FamilyName(m.kinematics.family) + ")"},
                         {"servo rate", fmt::format("{:g} Hz", m.servo_rate_hz)},
                         {"path", fmt::format("{} ({} points)", x.path.name, x.path.vertices.size())},
                         {"duration", fmt::format("{:.3f} s", x.trajectory.joints.size() * x.trajectory.dt_s)},
                         {"feed-forward kf (mean of axes)", fmt::format("{:.4f}", x.feed_forward.averaged)}});
  report::HtmlTable ff({"axis", "kf of the axis", "c_v kf=0 (ms)", "c_a kf=0 (ms²)", "c_v kf=1 (ms)", "c_a kf=1 (ms²)",
                        "c_j kf=1 (ms³)"},
                       "Identified model (from axis tests) and each moving axis's feed-forward coefficient");
  for (int a = 0; a < kAxisCount; ++a) {
    const auto& ax = model.axes[a];
    ff.AddRow({names[a], std::isnan(x.feed_forward.per_axis[a]) ? "(still)" : fmt::format("{:.4f}", x.feed_forward.per_axis[a]),
               fmt::format("{:.4f}", ax.without_ff[0] * 1e3), fmt::format("{:.5f}", ax.without_ff[1] * 1e6),
               fmt::format("{:.5f}", ax.full_ff[0] * 1e3), fmt::format("{:.5f}", ax.full_ff[1] * 1e6),
               fmt::format("{:.6f}", ax.full_ff[2] * 1e9)});
  }
  page.AddTable(ff);

  page.AddHeading("Contour error");
  report::HtmlTable t({"run", "rms (µm)", "max (µm)", "orientation rms (µrad)", "orientation max (µrad)",
                       "end point off (µm)", "rms vs FF alone", "saturated periods"});
  for (const SimulatedRun* run : {&x.without_ff, &x.with_ff, &x.corrected}) {
    std::int64_t sat = 0;
    for (auto s : run->saturated_periods) sat += s;
    t.AddRow({run->label, fmt::format("{:.3f}", run->contour.rms_um), fmt::format("{:.3f}", run->contour.max_um),
              fmt::format("{:.2f}", run->contour.rms_urad), fmt::format("{:.2f}", run->contour.max_urad),
              fmt::format("{:.3f}", run->contour.end_point_um),
              fmt::format("{:+.1f} %", -ReductionPercent(x.with_ff.contour.rms_um, run->contour.rms_um)),
              std::to_string(sat)});
  }
  page.AddTable(t);
  page.AddNote(fmt::format("Every run is judged standing at the end: the final rest was lengthened by {:.2f} s until "
                           "the model's predicted tracking error had decayed and by {:.2f} s more until the measured "
                           "positions stood; the corrected program ends on the programmed end point and its figures "
                           "are those of the written program re-run with that rest.",
                           x.end_rest_added_s, x.measured_rest_added_s));
  if (x.with_ff.saturated_periods != std::array<std::int64_t, kAxisCount>{})
    page.AddNote("A drive reached its current limit (saturated periods > 0): the linear model does not hold there.");

  {
    report::SvgChartOptions o;
    o.title = "Programmed tool tip path (workpiece frame, top view)";
    o.x_label = "X (mm)";
    o.y_label = "Y (mm)";
    o.y_includes_zero = false;
    report::SvgChart chart(o);
    const auto& v = x.path.vertices;
    chart.AddLine("tool tip", Thin(v.size(), [&](std::size_t i) { return v[i].tip_mm.x(); }),
                  Thin(v.size(), [&](std::size_t i) { return v[i].tip_mm.y(); }));
    page.AddChart(chart);
  }
  for (int part = 0; part < 2; ++part) {
    report::SvgChartOptions o;
    o.title = part == 0 ? "Contour error (tool tip) along the path" : "Tool orientation error along the path";
    o.x_label = "path length at the nearest point (mm)";
    o.y_label = part == 0 ? "contour error (µm)" : "orientation error (µrad)";
    report::SvgChart chart(o);
    for (const SimulatedRun* run : {&x.without_ff, &x.with_ff, &x.corrected}) {
      const auto& c = run->contour;
      const auto& y = part == 0 ? c.position_um : c.orientation_urad;
      chart.AddLine(run->label, Thin(y.size(), [&](std::size_t i) { return c.path_mm[i]; }),
                    Thin(y.size(), [&](std::size_t i) { return y[i]; }));
    }
    page.AddChart(chart);
    if (part == 0) {
      report::SvgChartOptions oz = o;
      oz.title = "Contour error, FF alone and FF + correction";
      report::SvgChart zoom(oz);
      for (const SimulatedRun* run : {&x.with_ff, &x.corrected}) {
        const auto& c = run->contour;
        zoom.AddLine(run->label, Thin(c.path_mm.size(), [&](std::size_t i) { return c.path_mm[i]; }),
                     Thin(c.path_mm.size(), [&](std::size_t i) { return c.position_um[i]; }));
      }
      page.AddChart(zoom);
    }
  }
  page.AddHeading("Per-axis tracking error (programmed command − actual)");
  // The corrected run is compared with the original command (what was programmed).
  const auto& cmd = x.trajectory.joints;
  auto tracking = [&](const SimulatedRun& run, int a, std::size_t i) { return (cmd[i][a] - run.actual[i][a]) * 1e3; };
  report::HtmlTable rms({"axis", "unit", "no FF rms", "FF rms", "FF + correction rms"}, "RMS tracking error per axis");
  for (int a = 0; a < kAxisCount; ++a) {
    std::vector<std::string> row = {names[a], a >= kTilt ? "mdeg" : "µm"};
    for (const SimulatedRun* run : {&x.without_ff, &x.with_ff, &x.corrected}) {
      double sum2 = 0;
      const std::size_t n = std::min(cmd.size(), run->actual.size());
      for (std::size_t i = 0; i < n; ++i) sum2 += tracking(*run, a, i) * tracking(*run, a, i);
      row.push_back(fmt::format("{:.3f}", n ? std::sqrt(sum2 / n) : 0.0));
    }
    rms.AddRow(row);
  }
  page.AddTable(rms);
  for (int a = 0; a < kAxisCount; ++a) {
    report::SvgChartOptions o;
    o.title = names[a] + " tracking error with feed-forward (no FF: table above)";
    o.x_label = "time (s)";
    o.y_label = a >= kTilt ? "error (mdeg)" : "error (µm)";
    o.height_px = 260;
    report::SvgChart chart(o);
    for (const SimulatedRun* run : {&x.with_ff, &x.corrected}) {
      const std::size_t n = std::min(cmd.size(), run->actual.size());
      chart.AddLine(run->label, Thin(n, [&](std::size_t i) { return i * x.trajectory.dt_s; }),
                    Thin(n, [&](std::size_t i) { return tracking(*run, a, i); }));
    }
    page.AddChart(chart);
  }
  page.AddNote("The corrected run replays the corrected program (G93 blocks, one per servo period) read back from its text.");
  return page;
}

}  // namespace trueaxis::fiveaxis
