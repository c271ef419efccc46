#include "trueaxis/analysis/evaluation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::analysis {
namespace {

constexpr double kSameTargetTolMm = 1e-6;  // as measure::Measurement::Targets()

struct Samples {
  std::vector<double> x;  // deviations, µm
  int first_line = 0;
};

double Mean(const std::vector<double>& v) {
  // Two-pass: mean of differences from the first value, so large common
  // offsets (e.g. -126 mm gear offsets converted to µm) lose no digits.
  const double ref = v.front();
  double sum = 0;
  for (double x : v) sum += x - ref;
  return ref + sum / static_cast<double>(v.size());
}

// Sample standard deviation (n − 1 in the denominator), ISO 230-2 "estimator
// of the unidirectional axis repeatability".
double StdDev(const std::vector<double>& v, double mean) {
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / static_cast<double>(v.size() - 1));
}

}  // namespace

bool EvaluationOptions::IsValid(std::string* why) const {
  if (!FindStandard(standard)) {
    if (why) {
      std::string names;
      for (const auto& n : StandardNames()) names += (names.empty() ? "" : ", ") + n;
      *why = fmt::format("unknown standard '{}'; known: {}", standard, names);
    }
    return false;
  }
  return true;
}

Evaluation Evaluate(const measure::Measurement& m, const EvaluationOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("EvaluationOptions: " + why);
  measure::ValidateForEvaluation(m);

  Evaluation ev;
  ev.standard = *FindStandard(options.standard);
  ev.source = m.source;
  ev.runs = static_cast<int>(m.Runs().size());
  // VDI 3441 has no coverage factor of its own; the ISO values that come
  // along with it use the current ISO factor.
  const double k = ev.standard.coverage_factor;

  const auto targets = m.Targets();
  std::vector<std::array<Samples, 2>> samples(targets.size());
  for (const auto& p : m.points) {
    auto it = std::lower_bound(targets.begin(), targets.end(), p.target_mm - kSameTargetTolMm);
    auto& s = samples[static_cast<std::size_t>(it - targets.begin())][DirectionIndex(p.direction)];
    s.x.push_back(p.deviation_um);
    if (s.first_line == 0 || (p.source_line > 0 && p.source_line < s.first_line)) s.first_line = p.source_line;
  }

  ev.targets.resize(targets.size());
  for (std::size_t i = 0; i < targets.size(); ++i) {
    for (int d = 0; d < 2; ++d) {
      if (samples[i][d].x.size() < 2)
        throw InputError(m.source, samples[i][d].first_line, "run",
                         fmt::format("target {} mm has {} run(s) in the '{}' direction; repeatability needs at least 2",
                                     targets[i], samples[i][d].x.size(), d == 0 ? '+' : '-'));
    }
    // Sort each sample so the sums do not depend on row order.
    for (auto& s : samples[i]) std::sort(s.x.begin(), s.x.end());
    auto& t = ev.targets[i];
    const auto& up = samples[i][0].x;
    const auto& down = samples[i][1].x;
    t.target_mm = targets[i];
    t.n_up = static_cast<int>(up.size());
    t.n_down = static_cast<int>(down.size());
    t.mean_up_um = Mean(up);
    t.mean_down_um = Mean(down);
    t.mean_um = (t.mean_up_um + t.mean_down_um) / 2;
    t.s_up_um = StdDev(up, t.mean_up_um);
    t.s_down_um = StdDev(down, t.mean_down_um);
    t.reversal_um = t.mean_up_um - t.mean_down_um;
    t.R_up_um = 2 * k * t.s_up_um;
    t.R_down_um = 2 * k * t.s_down_um;
    t.R_um = std::max({k * t.s_up_um + k * t.s_down_um + std::abs(t.reversal_um), t.R_up_um, t.R_down_um});
    t.vdi_scatter_um = 6 * (t.s_up_um + t.s_down_um) / 2;
    t.vdi_reversal_span_um = std::abs(t.reversal_um);
  }

  constexpr double kInf = std::numeric_limits<double>::infinity();
  double max_up = -kInf, min_up = kInf, max_dn = -kInf, min_dn = kInf, max_bi = -kInf, min_bi = kInf;
  double acc_up_hi = -kInf, acc_up_lo = kInf, acc_dn_hi = -kInf, acc_dn_lo = kInf;
  double vdi_hi = -kInf, vdi_lo = kInf, b_sum = 0, ps_sum = 0, u_sum = 0;
  auto& a = ev.axis;
  for (const auto& t : ev.targets) {
    max_up = std::max(max_up, t.mean_up_um), min_up = std::min(min_up, t.mean_up_um);
    max_dn = std::max(max_dn, t.mean_down_um), min_dn = std::min(min_dn, t.mean_down_um);
    max_bi = std::max(max_bi, t.mean_um), min_bi = std::min(min_bi, t.mean_um);
    acc_up_hi = std::max(acc_up_hi, t.mean_up_um + k * t.s_up_um);
    acc_up_lo = std::min(acc_up_lo, t.mean_up_um - k * t.s_up_um);
    acc_dn_hi = std::max(acc_dn_hi, t.mean_down_um + k * t.s_down_um);
    acc_dn_lo = std::min(acc_dn_lo, t.mean_down_um - k * t.s_down_um);
    a.B_um = std::max(a.B_um, std::abs(t.reversal_um));
    b_sum += t.reversal_um;
    a.R_up_um = std::max(a.R_up_um, t.R_up_um);
    a.R_down_um = std::max(a.R_down_um, t.R_down_um);
    a.R_um = std::max(a.R_um, t.R_um);
    const double half = (t.vdi_reversal_span_um + t.vdi_scatter_um) / 2;
    vdi_hi = std::max(vdi_hi, t.mean_um + half);
    vdi_lo = std::min(vdi_lo, t.mean_um - half);
    a.Ps_max_um = std::max(a.Ps_max_um, t.vdi_scatter_um);
    a.U_max_um = std::max(a.U_max_um, t.vdi_reversal_span_um);
    ps_sum += t.vdi_scatter_um;
    u_sum += t.vdi_reversal_span_um;
  }
  const double n = static_cast<double>(ev.targets.size());
  a.B_mean_um = b_sum / n;
  a.E_up_um = max_up - min_up;
  a.E_down_um = max_dn - min_dn;
  a.E_um = std::max(max_up, max_dn) - std::min(min_up, min_dn);
  a.M_um = max_bi - min_bi;
  a.A_up_um = acc_up_hi - acc_up_lo;
  a.A_down_um = acc_dn_hi - acc_dn_lo;
  a.A_um = std::max(acc_up_hi, acc_dn_hi) - std::min(acc_up_lo, acc_dn_lo);
  a.Pa_um = a.M_um;  // VDI Pa uses the same bidirectional means x̄_j
  a.P_um = vdi_hi - vdi_lo;
  a.Ps_mean_um = ps_sum / n;
  a.U_mean_um = u_sum / n;
  return ev;
}

namespace {
std::string F(double v) { return fmt::format("{:.4f}", v); }
}  // namespace

std::string Evaluation::BriefReport() const {
  std::string out = fmt::format("{}{}: {} targets × {} runs, k = {}\n", standard.name,
                                standard.requested_as.empty() || standard.requested_as == standard.name
                                    ? ""
                                    : fmt::format(" (as {})", standard.requested_as),
                                targets.size(), runs, standard.coverage_factor);
  out += fmt::format("A = {} µm  B = {} µm  E = {} µm  M = {} µm  R = {} µm\n", F(axis.A_um), F(axis.B_um),
                     F(axis.E_um), F(axis.M_um), F(axis.R_um));
  if (standard.is_vdi)
    out += fmt::format("VDI 3441: P = {} µm  Pa = {} µm  Ps max = {} µm  U max = {} µm\n", F(axis.P_um), F(axis.Pa_um),
                       F(axis.Ps_max_um), F(axis.U_max_um));
  return out;
}

std::string Evaluation::FullReport() const {
  std::string out = BriefReport();
  out += fmt::format("source: {}\n\n", source);
  struct Row {
    const char* name;
    const char* meaning;
    double value;
  };
  const Row rows[] = {
      {"A", "bidirectional accuracy", axis.A_um},
      {"A↑", "unidirectional accuracy (+)", axis.A_up_um},
      {"A↓", "unidirectional accuracy (-)", axis.A_down_um},
      {"B", "reversal value (max |B_i|)", axis.B_um},
      {"B̄", "mean reversal value", axis.B_mean_um},
      {"E", "bidirectional systematic positioning error", axis.E_um},
      {"E↑", "unidirectional systematic error (+)", axis.E_up_um},
      {"E↓", "unidirectional systematic error (-)", axis.E_down_um},
      {"M", "mean bidirectional positioning error", axis.M_um},
      {"R", "bidirectional repeatability", axis.R_um},
      {"R↑", "unidirectional repeatability (+)", axis.R_up_um},
      {"R↓", "unidirectional repeatability (-)", axis.R_down_um},
      {"P", "VDI 3441 positional uncertainty", axis.P_um},
      {"Pa", "VDI 3441 position deviation", axis.Pa_um},
      {"Ps max", "VDI 3441 max position scatter", axis.Ps_max_um},
      {"Ps mean", "VDI 3441 mean position scatter", axis.Ps_mean_um},
      {"U max", "VDI 3441 max reversal span", axis.U_max_um},
      {"U mean", "VDI 3441 mean reversal span", axis.U_mean_um},
  };
  for (const auto& r : rows) {
    // Pad by code points, not bytes (the arrows are multi-byte).
    std::string name = r.name;
    int width = 0;
    // Continuation bytes and combining marks (U+0300..U+036F, lead bytes 0xCC/0xCD) take no column.
    for (std::size_t b = 0; b < name.size(); ++b) {
      const auto c = static_cast<unsigned char>(name[b]);
      if ((c & 0xC0) == 0x80) continue;
      if (c == 0xCC || c == 0xCD) continue;
      ++width;
    }
    name.append(static_cast<std::size_t>(std::max(0, 8 - width)), ' ');
    out += fmt::format("  {}{:>10} µm   {}\n", name, F(r.value), r.meaning);
  }
  out += fmt::format("\n{:>12} {:>11} {:>11} {:>11} {:>9} {:>9} {:>10} {:>9} {:>9} {:>9}\n", "target_mm",
                     "mean_up_um", "mean_dn_um", "mean_um", "s_up_um", "s_dn_um", "B_i_um", "R_up_um", "R_dn_um",
                     "R_i_um");
  for (const auto& t : targets)
    out += fmt::format("{:>12.4f} {:>11.4f} {:>11.4f} {:>11.4f} {:>9.4f} {:>9.4f} {:>10.4f} {:>9.4f} {:>9.4f} {:>9.4f}\n",
                       t.target_mm, t.mean_up_um, t.mean_down_um, t.mean_um, t.s_up_um, t.s_down_um, t.reversal_um,
                       t.R_up_um, t.R_down_um, t.R_um);
  return out;
}

}  // namespace trueaxis::analysis
