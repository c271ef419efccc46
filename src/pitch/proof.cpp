#include "trueaxis/pitch/proof.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::pitch {

PositioningFigures Figures(const measure::Measurement& m) {
  PositioningFigures f;
  const analysis::Evaluation ev = analysis::Evaluate(m);
  f.targets = static_cast<int>(ev.targets.size());
  f.iso = ev.axis;
  for (const auto& p : m.points) f.max_error_um = std::max(f.max_error_um, std::abs(p.deviation_um));
  double ss = 0, dof = 0;
  for (const auto& t : ev.targets) {
    ss += (t.n_up - 1) * t.s_up_um * t.s_up_um + (t.n_down - 1) * t.s_down_um * t.s_down_um;
    dof += (t.n_up - 1) + (t.n_down - 1);
  }
  f.repeatability_3s_um = dof > 0 ? 3 * std::sqrt(ss / dof) : 0.0;
  double sum = 0, sum_sq = 0;
  for (const auto& p : m.points) sum += p.deviation_um;
  const double mean = sum / static_cast<double>(m.points.size());
  for (const auto& p : m.points) sum_sq += (p.deviation_um - mean) * (p.deviation_um - mean);
  f.uncertainty_um = m.points.size() > 1 ? 3 * std::sqrt(sum_sq / static_cast<double>(m.points.size() - 1)) : 0.0;
  return f;
}

measure::Measurement AtGrid(const measure::Measurement& m, double reference_mm, double spacing_mm) {
  measure::Measurement out = m;
  out.points.clear();
  for (const auto& p : m.points) {
    const double k = (p.target_mm - reference_mm) / spacing_mm;
    if (std::abs(k - std::round(k)) * spacing_mm <= 1e-3) out.points.push_back(p);
  }
  return out;
}

std::vector<FollowingPoint> FollowingErrorVsFeed(const sim::MachineDescription& machine, std::size_t axis,
                                                 const PitchErrorTable& table, const std::vector<double>& feeds,
                                                 const sim::InterpolatorOptions& interpolator, std::uint64_t seed) {
  const double lo = table.VouchedFromMm();
  const double hi = std::min(table.VouchedToMm(), lo + 300.0);
  // Every feed is checked before anything runs: the work of one is ∝ its move's duration.
  for (double feed : feeds) {
    if (auto why = ImplausibleFeedMmPerMin(feed)) throw InputError("command line", 0, "--feeds", *why);
    const double duration_s = (hi - lo) / (feed / 60);
    if (duration_s > kMaxFollowingMoveS)
      throw InputError("command line", 0, "--feeds",
                       fmt::format("{:g} mm/min over the {:g} mm move takes {:.3g} s of simulated motion; the "
                                   "following-error comparison simulates at most {:g} s per feed (a feed of at least "
                                   "{:.3g} mm/min)",
                                   feed, hi - lo, duration_s, kMaxFollowingMoveS, (hi - lo) * 60 / kMaxFollowingMoveS));
  }
  std::vector<FollowingPoint> out;
  for (double feed : feeds) {
    FollowingPoint fp;
    fp.feed_mm_min = feed;
    for (auto mode : {sim::FeedForward::kAhead, sim::FeedForward::kLate}) {
      sim::VirtualMachine vm(machine, seed);
      sim::InterpolatorOptions io = interpolator;
      io.mode = mode;
      sim::CncInterpolator ipo(vm, axis, io, [&table](double x, int dir) { return CorrectionUm(table, x, dir); });
      ipo.MoveTo(lo, 2000);  // into position, then a forward approach so the play is taken up
      ipo.MoveTo(lo + std::min(1.0, (hi - lo) / 10), 2000);
      (mode == sim::FeedForward::kAhead ? fp.ahead : fp.late) = ipo.MoveTo(hi, feed);
    }
    out.push_back(fp);
  }
  return out;
}

measure::Measurement InVouchedRange(const measure::Measurement& m, const PitchErrorTable& table, bool inside) {
  measure::Measurement out = m;
  out.points.clear();
  for (const auto& p : m.points)
    if (table.OutsideVouchedRange(p.target_mm) != inside) out.points.push_back(p);
  return out;
}

PitchComparison ComparePitch(const measure::Measurement& before_all, const measure::Measurement& after_all,
                             const PitchErrorTable& table) {
  PitchComparison c;
  c.vouched_from_mm = table.VouchedFromMm();
  c.vouched_to_mm = table.VouchedToMm();
  const measure::Measurement before = InVouchedRange(before_all, table);
  const measure::Measurement after = InVouchedRange(after_all, table);
  if (before.points.empty() || after.points.empty())
    throw InputError(after_all.source, 0, "target_mm",
                     fmt::format("no target lies in the range the pitch table vouches for ({}…{} mm)",
                                 c.vouched_from_mm, c.vouched_to_mm));
  const auto max_abs = [](const measure::Measurement& m) {
    double worst = 0;
    for (const auto& p : m.points) worst = std::max(worst, std::abs(p.deviation_um));
    return worst;
  };
  const measure::Measurement after_out = InVouchedRange(after_all, table, false);
  std::vector<double> outside_targets;
  for (const auto& p : after_out.points) outside_targets.push_back(std::round(p.target_mm * 1e3));
  std::sort(outside_targets.begin(), outside_targets.end());
  c.outside_targets = static_cast<int>(std::unique(outside_targets.begin(), outside_targets.end()) - outside_targets.begin());
  c.outside_after_max_um = max_abs(after_out);
  c.outside_before_max_um = max_abs(InVouchedRange(before_all, table, false));
  c.before = Figures(before);
  c.after = Figures(after);
  c.before_at_lead = Figures(AtGrid(before, table.reference_mm, table.lead_mm));
  c.after_at_lead = Figures(AtGrid(after, table.reference_mm, table.lead_mm));
  c.interpolation_error_um = MaxInterpolationErrorUm(table, before);
  for (const auto& t : analysis::Evaluate(AtGrid(after, table.reference_mm, table.lead_mm)).targets)
    c.drift_um = std::max(c.drift_um, std::abs(t.mean_um));
  return c;
}

std::string PitchComparison::Dominant() const {
  if (drift_um > interpolation_error_um && drift_um > after.repeatability_3s_um) return "drift";
  return interpolation_error_um >= after.repeatability_3s_um ? "interpolation" : "repeatability";
}

std::string PitchProofResult::Report() const {
  std::string s = fmt::format("{} axis {}: travel {} mm, lead {} mm, table {} points (once per {:.4g} mm), verified at {} targets\n",
                              machine, axis, travel_mm, lead_mm, table.size(), table.SpacingMm(), c.after.targets);
  if (samples_choice) s += "  table: " + samples_choice->Describe() + "\n";
  auto line = [](const char* what, const PositioningFigures& b, const PositioningFigures& a) {
    return fmt::format("  {:<22} max error {:7.3f} -> {:6.3f} um   error band 3s {:6.3f} -> {:6.3f} um   "
                       "A {:7.3f} -> {:6.3f}  E {:7.3f} -> {:6.3f}  R {:6.3f} -> {:6.3f}  B {:6.3f} -> {:6.3f} um\n",
                       what, b.max_error_um, a.max_error_um, b.uncertainty_um, a.uncertainty_um, b.iso.A_um, a.iso.A_um,
                       b.iso.E_um, a.iso.E_um, b.iso.R_um, a.iso.R_um, b.iso.B_um, a.iso.B_um);
  };
  s += line("at every fine target", c.before, c.after);
  s += line("at lead points only", c.before_at_lead, c.after_at_lead);
  s += fmt::format("  residual: table interpolation error {:.3f} um, repeatability 3s {:.3f} um (run to run), drift at the "
                   "lead points {:.3f} um (homing shift {:.3f} um) -> {} dominates\n",
                   c.interpolation_error_um, c.after.repeatability_3s_um, c.drift_um, homing_shift_um, c.Dominant());
  if (c.outside_targets > 0)
    s += fmt::format("  outside the table's measured range {:g}…{:g} mm (end values held, not in the figures above): {} "
                     "targets, max error {:.3f} -> {:.3f} um\n",
                     c.vouched_from_mm, c.vouched_to_mm, c.outside_targets, c.outside_before_max_um, c.outside_after_max_um);
  for (const auto& f : following)
    s += fmt::format("  feed {:6.0f} mm/min: following error of the correction max {:.3f} (ahead) vs {:.3f} um (late)\n",
                     f.feed_mm_min, f.ahead.max_abs_following_um, f.late.max_abs_following_um);
  return s;
}

PitchProofResult RunPitchProof(const sim::MachineDescription& machine, std::size_t axis, const PitchProofOptions& o) {
  PitchProofResult r;
  const auto& ad = machine.axes.at(axis);
  r.machine = machine.name;
  r.axis = ad.name;
  r.lead_mm = ad.lead_mm;
  r.travel_mm = ad.travel_mm;
  FineSessionOptions so;
  so.seed = o.seed;
  so.homing = o.homing;
  so.cycle = o.cycle;
  so.interpolator = o.interpolator;
  const FineSessionResult before = RunFineSession(machine, axis, so);
  r.before_run = before.measurement;
  TableFromMeasurementOptions to;
  to.lead_mm = ad.lead_mm;
  to.samples_per_lead = o.samples_per_lead;
  to.reference_mm = ad.reference_mm;
  if (o.samples_per_lead == 0) {
    r.samples_choice = ChooseSamplesPerLead(r.before_run, to);
    to.samples_per_lead = r.samples_choice->samples_per_lead;
  }
  r.table = TableFromMeasurement(r.before_run, to);
  so.day = o.verify_day;
  so.table = &r.table;
  const FineSessionResult after = RunFineSession(machine, axis, so);
  r.after_run = after.measurement;
  r.outside_table_lookups = after.outside_table_lookups;
  r.homing_shift_um = after.homing.offset_um - after.calibration_homing.offset_um;
  r.c = ComparePitch(r.before_run, r.after_run, r.table);
  r.following = FollowingErrorVsFeed(machine, axis, r.table, o.feeds_mm_min, o.interpolator, o.seed);
  return r;
}

}  // namespace trueaxis::pitch
