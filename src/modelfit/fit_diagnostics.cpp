#include "trueaxis/core/median.hpp"
#include "trueaxis/modelfit/fit_diagnostics.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>

namespace trueaxis::model {
namespace {

StateResidualShape Shape(const StateResidualInput& s) {
  StateResidualShape out;
  out.label = s.label;
  out.cold = s.cold;
  const std::size_t n = std::min(s.position_mm.size(), s.residual_um.size());
  out.points = n;
  if (n == 0) return out;
  double mx = 0, my = 0, lo = s.position_mm[0], hi = s.position_mm[0];
  for (std::size_t i = 0; i < n; ++i) {
    mx += s.position_mm[i], my += s.residual_um[i];
    lo = std::min(lo, s.position_mm[i]), hi = std::max(hi, s.position_mm[i]);
  }
  mx /= static_cast<double>(n), my /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = s.position_mm[i] - mx;
    sxx += dx * dx, sxy += dx * (s.residual_um[i] - my);
  }
  const double b_um_per_mm = sxx > 0 ? sxy / sxx : 0;
  double ss_all = 0, ss_left = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double r = s.residual_um[i];
    ss_all += r * r;
    ss_left += std::pow(r - my - b_um_per_mm * (s.position_mm[i] - mx), 2);
  }
  out.offset_um = my;
  out.slope_um_per_m = 1000 * b_um_per_mm;
  out.end_to_end_um = b_um_per_mm * (hi - lo);
  out.pattern_rms_um = std::sqrt(ss_left / static_cast<double>(n));
  out.residual_rms_um = std::sqrt(ss_all / static_cast<double>(n));
  return out;
}

double MedianOrZero(const std::vector<double>& v) { return v.empty() ? 0.0 : Median(v); }

// Where a sensor would see a tilt along the travel that no key follows.
constexpr const char* kStructureSensor =
    "a sensor on the structure between the fixed bearing and the measuring point, or on the bed's top and bottom "
    "(a gradient bends the axis)";

std::string F(double v, int d = 2) { return fmt::format("{:.{}f}", v, d); }

}  // namespace

ResidualDiagnosis DiagnoseResidual(const ResidualDiagnosisInput& in) {
  ResidualDiagnosis d;
  d.cross_validated = in.cross_validated;
  for (const auto& s : in.states) d.states.push_back(Shape(s));

  // The states judged for structure: the heated ones (a cold state's residual is the geometric
  // fit's own), or every state when there are fewer than two heated.
  std::vector<const StateResidualShape*> judged;
  for (const auto& s : d.states)
    if (!s.cold && s.points >= 3) judged.push_back(&s);
  if (judged.size() < 2) {
    judged.clear();
    for (const auto& s : d.states)
      if (s.points >= 3) judged.push_back(&s);
  }
  {
    // Two standard errors of a state's offset (σ/√n) and of its end-to-end slope (σ·√12/√n for
    // targets spread evenly over the travel), σ the median pattern RMS; never below the cold
    // runs' repeatability.
    std::vector<double> p, n;
    for (const auto* s : judged) p.push_back(s->pattern_rms_um), n.push_back(static_cast<double>(s->points));
    const double se = MedianOrZero(p) / std::sqrt(std::max(1.0, MedianOrZero(n)));
    const double rep = std::isfinite(in.noise_um) ? in.noise_um : 0.0;
    d.offset_level_um = std::max(rep, 2 * se);
    d.slope_level_um = std::max(rep, 2 * std::sqrt(12.0) * se);
    d.noise_source = rep >= 2 * se ? "repeatability of the cold runs"
                                   : fmt::format("scatter of the states (two standard errors of {} µm)", F(MedianOrZero(p)));
  }

  // Key sensors' shares of the thermal correction (mean squares over every point of every state).
  std::vector<double> ms(in.key_sensors.size(), 0.0);
  std::size_t npts = 0;
  for (const auto& s : in.states) {
    const std::size_t n = s.position_mm.size();
    npts += n;
    for (std::size_t k = 0; k < ms.size() && k < s.key_contribution_um.size(); ++k)
      for (std::size_t i = 0; i < n && i < s.key_contribution_um[k].size(); ++i)
        if (std::isfinite(s.key_contribution_um[k][i])) ms[k] += s.key_contribution_um[k][i] * s.key_contribution_um[k][i];
  }
  double total = 0;
  for (double& m : ms) m /= static_cast<double>(std::max<std::size_t>(1, npts)), total += m;
  for (std::size_t k = 0; k < ms.size(); ++k)
    d.key_shares.push_back({in.key_sensors[k], std::sqrt(ms[k]), total > 0 ? 100 * ms[k] / total : 0.0});

  const std::string where = in.cross_validated ? "held-out" : "in-sample";
  const std::size_t nj = judged.size();
  if (nj < 2) {
    d.findings.push_back("too few states to judge a structure in the residual");
    return d;
  }
  const std::size_t most = nj / 2 + 1;  // a majority
  auto count_sig = [&](auto value, double level, int sign) {
    std::size_t c = 0;
    for (const auto* s : judged) {
      const double v = value(*s);
      if (std::abs(v) > level && (sign == 0 || (v > 0) == (sign > 0))) ++c;
    }
    return c;
  };
  auto end_to_end = [](const StateResidualShape& s) { return s.end_to_end_um; };
  auto offset = [](const StateResidualShape& s) { return s.offset_um; };
  auto range_of = [&](auto value) {
    double lo = value(*judged[0]), hi = lo;
    for (const auto* s : judged) lo = std::min(lo, value(*s)), hi = std::max(hi, value(*s));
    return std::array<double, 2>{lo, hi};
  };

  for (int sign : {+1, -1}) {
    // Consistent: a majority tilts this way, and fewer than a third as many the other way.
    const std::size_t c = count_sig(end_to_end, d.slope_level_um, sign);
    const std::size_t against = count_sig(end_to_end, d.slope_level_um, -sign);
    if (c < most || 3 * against >= c) continue;
    d.slope_structure = true;
    std::vector<double> slopes;
    for (const auto* s : judged) slopes.push_back(s->slope_um_per_m);
    const auto r = range_of(end_to_end);
    d.findings.push_back(fmt::format(
        "slope: in {} of {} states the {} residual {} along the travel ({} to {} µm end to end, median {} µm/m), "
        "more than the noise level {} µm: the model misses a bending or stretching of the axis that no key sensor "
        "follows; {} would help.",
        c, nj, where, sign > 0 ? "rises" : "falls", F(r[0]), F(r[1]), F(MedianOrZero(slopes), 1), F(d.slope_level_um),
        kStructureSensor));
  }
  if (!d.slope_structure) {
    const std::size_t c = count_sig(end_to_end, d.slope_level_um, 0);
    if (c >= most) {
      const auto r = range_of(end_to_end);
      d.findings.push_back(fmt::format("slope of changing sign: in {} of {} states the {} residual tilts by more than "
                                       "{} µm end to end, up in some and down in others ({} to {} µm): the keys' "
                                       "gains do not follow the axis's tilt from state to state; {} may.",
                                       c, nj, where, F(d.slope_level_um), F(r[0]), F(r[1]), kStructureSensor));
    }
  }
  const std::size_t c_off = count_sig(offset, d.offset_level_um, 0);
  if (c_off >= most) {
    d.offset_structure = true;
    const auto r = range_of(offset);
    const std::size_t pos = count_sig(offset, d.offset_level_um, +1), neg = count_sig(offset, d.offset_level_um, -1);
    const bool same_sign = pos == 0 || neg == 0;  // every offset above the level on one side
    d.findings.push_back(fmt::format(
        "offset: in {} of {} states the {} residual is shifted by more than the noise level {} µm ({} to {} µm){}: "
        "the whole axis moves in a way no key sensor follows. The room/ambient sensor or a sensor on the column "
        "would help.",
        c_off, nj, where, F(d.offset_level_um), F(r[0]), F(r[1]),
        same_sign ? ", always the same sign" : ", changing from state to state"));
  }
  if (d.findings.empty())
    d.findings.push_back(fmt::format("no structure: in most states the {} residual's offset stays within {} µm and "
                                     "its end-to-end slope within {} µm (the noise levels); what is left is scatter "
                                     "or a pattern along the travel",
                                     where, F(d.offset_level_um), F(d.slope_level_um)));
  return d;
}

std::string ResidualDiagnosisBrief(const ResidualDiagnosis& d) {
  std::string out = fmt::format("  residual ({}; noise levels: offset {} µm, end-to-end slope {} µm, from the {}):\n",
                                d.cross_validated ? "cross-validated" : "in-sample", F(d.offset_level_um),
                                F(d.slope_level_um), d.noise_source);
  for (const auto& f : d.findings) out += "    " + f + "\n";
  if (!d.key_shares.empty()) {
    out += "    key sensor share of the thermal correction:";
    for (const auto& k : d.key_shares) out += fmt::format(" {} {} % ({} µm RMS);", k.sensor, F(k.share_pct, 0), F(k.rms_um));
    out.back() = '\n';
  }
  return out;
}

std::string ResidualDiagnosisTable(const ResidualDiagnosis& d) {
  std::string out = fmt::format("residual shape per state ({}; µm, slope µm/m):\n",
                                d.cross_validated ? "cross-validated" : "in-sample");
  out += fmt::format("  {:<16} {:>6} {:>9} {:>9} {:>11} {:>11} {:>9}\n", "state", "points", "offset", "slope/m",
                     "end-to-end", "pattern RMS", "RMS");
  for (const auto& s : d.states)
    out += fmt::format("  {:<16} {:>6} {:>9} {:>9} {:>11} {:>11} {:>9}{}\n", s.label, s.points, F(s.offset_um),
                       F(s.slope_um_per_m, 1), F(s.end_to_end_um), F(s.pattern_rms_um), F(s.residual_rms_um),
                       s.cold ? "  (cold)" : "");
  return out;
}

}  // namespace trueaxis::model
