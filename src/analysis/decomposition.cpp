#include "trueaxis/analysis/decomposition.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace trueaxis::analysis {
namespace {
constexpr double kTwoPi = 2 * std::numbers::pi;
}

bool DecompositionOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!std::isfinite(lead_mm) || lead_mm < 0) return fail("lead_mm must be >= 0 (0 = unknown)");
  if (trend_degree < 0 || trend_degree > 3) return fail("trend_degree must be in 0..3");
  if (harmonics < 0 || harmonics > 20) return fail("harmonics must be in 0..20");
  if (!std::isfinite(band_sigmas) || band_sigmas <= 0) return fail("band_sigmas must be > 0");
  return true;
}

bool Decomposition::periodic_fitted() const {
  return std::any_of(harmonics.begin(), harmonics.end(), [](const auto& h) { return h.resolved; });
}

double Decomposition::Progressive(double x_mm) const {
  double v = 0, p = 1;
  for (double c : trend_coefficients) v += c * p, p *= (x_mm - trend_origin_mm);
  return v;
}

double Decomposition::Periodic(double x_mm) const {
  double v = 0;
  for (const auto& h : harmonics)
    if (h.resolved) v += h.amplitude_um * std::sin(kTwoPi * x_mm / h.period_mm + h.phase_rad);
  return v;
}

Decomposition Decompose(const Evaluation& ev, const DecompositionOptions& options) {
  std::string why;
  if (!options.IsValid(&why)) throw std::invalid_argument("DecompositionOptions: " + why);
  Decomposition d;
  d.options = options;
  const auto& t = ev.targets;
  const int n = static_cast<int>(t.size());
  if (n == 0) return d;
  d.trend_origin_mm = t.front().target_mm;

  // Pooled σ of the run-to-run scatter: sqrt(Σ (n−1)s² / Σ (n−1)).
  double ss = 0, dof = 0;
  for (const auto& r : t) {
    ss += (r.n_up - 1) * r.s_up_um * r.s_up_um + (r.n_down - 1) * r.s_down_um * r.s_down_um;
    dof += (r.n_up - 1) + (r.n_down - 1);
  }
  d.sigma_um = dof > 0 ? std::sqrt(ss / dof) : 0;

  d.min_gap_mm = n > 1 ? std::numeric_limits<double>::infinity() : 0;
  for (int i = 1; i < n; ++i) {
    const double gap = t[i].target_mm - t[i - 1].target_mm;
    d.min_gap_mm = std::min(d.min_gap_mm, gap);
    d.max_gap_mm = std::max(d.max_gap_mm, gap);
  }

  // Trend degree cannot exceed what the targets support.
  const int degree = std::min(options.trend_degree, n - 1);
  if (degree < options.trend_degree)
    d.notes.push_back(fmt::format("progressive part reduced to degree {}: only {} targets", degree, n));

  // Harmonics: keep those sampled at better than 2 points per period.
  if (options.lead_mm <= 0) {
    if (options.harmonics > 0)
      d.notes.push_back("no screw lead given (--lead-mm or a 'lead_mm' metadata line): periodic part not fitted");
  } else {
    for (int h = 1; h <= options.harmonics; ++h) {
      Harmonic hm;
      hm.order = h;
      hm.period_mm = options.lead_mm / h;
      if (n < 2 || d.max_gap_mm >= hm.period_mm / 2) {
        hm.note = fmt::format(
            "aliased: targets up to {:.4g} mm apart sample this {:.4g} mm period fewer than 2 times per period "
            "(need every gap < {:.4g} mm)",
            d.max_gap_mm, hm.period_mm, hm.period_mm / 2);
      } else {
        hm.resolved = true;
      }
      d.harmonics.push_back(hm);
    }
  }
  auto resolved_count = [&] {
    return static_cast<int>(std::count_if(d.harmonics.begin(), d.harmonics.end(), [](auto& h) { return h.resolved; }));
  };
  // Keep at least one residual degree of freedom: drop the highest harmonics first.
  while (resolved_count() > 0 && degree + 1 + 2 * resolved_count() > n - 1) {
    for (auto it = d.harmonics.rbegin(); it != d.harmonics.rend(); ++it)
      if (it->resolved) {
        it->resolved = false;
        it->note = fmt::format("under-determined: {} targets cannot support the trend plus {} harmonic terms", n,
                               resolved_count() + 1);
        break;
      }
  }
  if (!d.harmonics.empty() && resolved_count() == 0)
    d.notes.push_back(fmt::format(
        "periodic part not determined: the target spacing ({:.4g}..{:.4g} mm) is too coarse for the {:.4g} mm lead; "
        "the periodic error is aliased into the other parts. Measure with a spacing below {:.4g} mm over a few "
        "leads to resolve it.",
        d.min_gap_mm, d.max_gap_mm, options.lead_mm, options.lead_mm / 2));

  // Design matrix: 1, (x−x0), …, then sin/cos per resolved harmonic.
  const int cols = degree + 1 + 2 * resolved_count();
  Eigen::MatrixXd A(n, cols);
  Eigen::VectorXd y(n);
  // Scale x for conditioning of the polynomial columns.
  const double span = std::max(1e-9, t.back().target_mm - t.front().target_mm);
  for (int i = 0; i < n; ++i) {
    const double x = t[i].target_mm;
    const double u = (x - d.trend_origin_mm) / span;
    double p = 1;
    for (int c = 0; c <= degree; ++c) A(i, c) = p, p *= u;
    int c = degree + 1;
    for (const auto& h : d.harmonics) {
      if (!h.resolved) continue;
      A(i, c++) = std::sin(kTwoPi * x / h.period_mm);
      A(i, c++) = std::cos(kTwoPi * x / h.period_mm);
    }
    y(i) = t[i].mean_um;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);
  if (qr.rank() < cols) {
    // Non-uniform but unlucky spacing can still make sin/cos collinear with the trend.
    d.notes.push_back("least-squares system is rank-deficient for this target set; periodic part not fitted");
    for (auto& h : d.harmonics)
      if (h.resolved) h.resolved = false, h.note = "rank-deficient with this target set";
    Eigen::MatrixXd At = A.leftCols(degree + 1);
    Eigen::VectorXd c = At.colPivHouseholderQr().solve(y);
    A = At;
    qr.compute(A);
  }
  const Eigen::VectorXd coef = qr.solve(y);
  d.trend_coefficients.assign(degree + 1, 0.0);
  for (int c = 0; c <= degree; ++c) d.trend_coefficients[c] = coef(c) / std::pow(span, c);
  int c = degree + 1;
  for (auto& h : d.harmonics) {
    if (!h.resolved) continue;
    const double a = coef(c++), b = coef(c++);  // a·sin + b·cos = A·sin(θ + φ)
    h.amplitude_um = std::hypot(a, b);
    h.phase_rad = std::atan2(b, a);
  }
  double rss = 0;
  for (int i = 0; i < n; ++i) {
    DecompositionPoint p;
    p.target_mm = t[i].target_mm;
    p.mean_um = t[i].mean_um;
    p.progressive_um = d.Progressive(p.target_mm);
    p.periodic_um = d.Periodic(p.target_mm);
    p.residual_um = p.mean_um - p.progressive_um - p.periodic_um;
    rss += p.residual_um * p.residual_um;
    d.points.push_back(p);
  }
  d.residual_rms_um = std::sqrt(rss / n);
  return d;
}

std::string Decomposition::BriefReport() const {
  std::string out = "progressive: ";
  for (std::size_t i = 0; i < trend_coefficients.size(); ++i) {
    const double c = trend_coefficients[i] * (i == 0 ? 1 : std::pow(1000.0, static_cast<double>(i)));
    out += fmt::format("{}{:+.4f} {}", i ? " " : "", c, i == 0 ? "µm" : i == 1 ? "µm/m·x" : fmt::format("µm/m^{}·x^{}", i, i));
  }
  out += fmt::format("\nperiodic: ");
  if (!periodic_fitted()) out += "not determined";
  for (const auto& h : harmonics)
    if (h.resolved) out += fmt::format("h{} ({:.4g} mm) {:.4f} µm; ", h.order, h.period_mm, h.amplitude_um);
  out += fmt::format("\nrandom: σ = {:.4f} µm, ±{}σ = ±{:.4f} µm; unexplained systematic RMS {:.4f} µm\n", sigma_um,
                     options.band_sigmas, options.band_sigmas * sigma_um, residual_rms_um);
  return out;
}

std::string Decomposition::FullReport() const {
  std::string out = BriefReport();
  for (const auto& h : harmonics)
    if (!h.resolved) out += fmt::format("  harmonic {} ({:.4g} mm): {}\n", h.order, h.period_mm, h.note);
  for (const auto& n : notes) out += "  note: " + n + "\n";
  out += fmt::format("{:>12} {:>10} {:>12} {:>10} {:>10}\n", "target_mm", "mean_um", "progress_um", "period_um",
                     "resid_um");
  for (const auto& p : points)
    out += fmt::format("{:>12.4f} {:>10.3f} {:>12.3f} {:>10.3f} {:>10.3f}\n", p.target_mm, p.mean_um, p.progressive_um,
                       p.periodic_um, p.residual_um);
  return out;
}

}  // namespace trueaxis::analysis
