#include "trueaxis/modelfit/polynomial_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace trueaxis::model {

std::vector<double> FitPolynomial(std::span<const double> u, std::span<const double> y, int degree) {
  if (degree < 0) throw std::invalid_argument("polynomial degree must be >= 0");
  if (u.size() != y.size()) throw std::invalid_argument("u and y differ in length");
  const auto n = static_cast<Eigen::Index>(u.size());
  if (n <= degree) throw std::invalid_argument(fmt::format("degree {} needs more than {} points", degree, n));
  Eigen::MatrixXd a(n, degree + 1);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    double p = 1;
    for (int j = 0; j <= degree; ++j, p *= u[static_cast<std::size_t>(i)]) a(i, j) = p;
    b(i) = y[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd c = a.colPivHouseholderQr().solve(b);
  return {c.data(), c.data() + c.size()};
}

double EvaluatePolynomial(std::span<const double> coefficients, double u) {
  double acc = 0;
  for (auto it = coefficients.rbegin(); it != coefficients.rend(); ++it) acc = acc * u + *it;
  return acc;
}

DegreeSelection SelectPolynomialDegree(std::span<const double> x, std::span<const double> y, double center_mm,
                                       double half_span_mm, int max_degree, double noise_um) {
  const std::size_t n = x.size();
  if (n < 2 || y.size() != n) throw std::invalid_argument("degree selection needs >= 2 targets");
  std::vector<double> u(n);
  for (std::size_t i = 0; i < n; ++i) u[i] = (x[i] - center_mm) / half_span_mm;

  DegreeSelection sel;
  sel.noise_um = noise_um;
  const int top = std::max(1, std::min(max_degree, static_cast<int>(n) - 2));
  for (int d = 1; d <= top; ++d) {
    DegreeCandidate c;
    c.degree = d;
    const auto coef = FitPolynomial(u, y, d);
    double ss = 0;
    for (std::size_t i = 0; i < n; ++i) ss += std::pow(y[i] - EvaluatePolynomial(coef, u[i]), 2);
    c.fit_rms_um = std::sqrt(ss / static_cast<double>(n));
    if (static_cast<int>(n) - 1 > d) {
      double cv = 0;
      std::vector<double> uu, yy;
      for (std::size_t k = 0; k < n; ++k) {
        uu.clear();
        yy.clear();
        for (std::size_t i = 0; i < n; ++i)
          if (i != k) uu.push_back(u[i]), yy.push_back(y[i]);
        const auto ck = FitPolynomial(uu, yy, d);
        cv += std::pow(y[k] - EvaluatePolynomial(ck, u[k]), 2);
      }
      c.cv_rms_um = std::sqrt(cv / static_cast<double>(n));
    }
    sel.candidates.push_back(c);
  }

  double cv_min = std::numeric_limits<double>::infinity();
  for (const auto& c : sel.candidates)
    if (std::isfinite(c.cv_rms_um)) cv_min = std::min(cv_min, c.cv_rms_um);
  if (!std::isfinite(cv_min)) {
    // Two targets (or three with degree 1): nothing to cross-validate; a line is all the data supports.
    sel.degree = 1;
    sel.rule = fmt::format("{} targets: too few to cross-validate, degree 1 (a line through them)", n);
    return sel;
  }
  if (std::isfinite(noise_um)) {
    sel.threshold_um = std::sqrt(cv_min * cv_min + noise_um * noise_um);
  } else {
    sel.threshold_um = 1.05 * cv_min;
  }
  for (const auto& c : sel.candidates) {
    if (std::isfinite(c.cv_rms_um) && c.cv_rms_um <= sel.threshold_um) {
      sel.degree = c.degree;
      break;
    }
  }
  if (std::isfinite(noise_um)) {
    sel.rule = fmt::format(
        "smallest degree whose leave-one-target-out CV RMS is within the run-to-run noise of the best: "
        "CV ≤ √(CV_min² + s_mean²) = √({:.3f}² + {:.3f}²) = {:.3f} µm → degree {}",
        cv_min, noise_um, sel.threshold_um, sel.degree);
  } else {
    sel.rule = fmt::format(
        "one run, so no run-to-run noise: smallest degree whose leave-one-target-out CV RMS is within 5 % of the "
        "best ({:.3f} µm) → degree {}",
        cv_min, sel.degree);
  }
  return sel;
}

double TableCrossValidationRms(std::span<const double> x, std::span<const double> y) {
  const std::size_t n = x.size();
  if (n < 2) return std::numeric_limits<double>::quiet_NaN();
  double ss = 0;
  for (std::size_t k = 0; k < n; ++k) {
    double pred;
    if (k == 0) pred = y[1];                 // end value held
    else if (k == n - 1) pred = y[n - 2];
    else {
      const double t = (x[k] - x[k - 1]) / (x[k + 1] - x[k - 1]);
      pred = y[k - 1] + t * (y[k + 1] - y[k - 1]);
    }
    ss += std::pow(y[k] - pred, 2);
  }
  return std::sqrt(ss / static_cast<double>(n));
}

double LeaveOneRunOutRms(std::span<const double> x, const std::vector<std::vector<double>>& deviation_by_run,
                         int degree, double center_mm, double half_span_mm) {
  const std::size_t runs = deviation_by_run.size(), n = x.size();
  if (runs < 3 || n < 2) return std::numeric_limits<double>::quiet_NaN();
  double ss = 0;
  std::size_t count = 0;
  for (std::size_t j = 0; j < runs; ++j) {
    std::vector<double> xs, means;
    for (std::size_t k = 0; k < n; ++k) {
      double sum = 0;
      int m = 0;
      for (std::size_t r = 0; r < runs; ++r)
        if (r != j && k < deviation_by_run[r].size() && std::isfinite(deviation_by_run[r][k]))
          sum += deviation_by_run[r][k], ++m;
      if (m > 0) xs.push_back(x[k]), means.push_back(sum / m);
    }
    if (xs.size() < 2) continue;
    std::vector<double> coeff;
    if (degree >= 0) {
      std::vector<double> u;
      for (double v : xs) u.push_back((v - center_mm) / half_span_mm);
      const int d = std::min<int>(degree, static_cast<int>(xs.size()) - 1);
      coeff = FitPolynomial(u, means, d);
    }
    for (std::size_t k = 0; k < n; ++k) {
      if (k >= deviation_by_run[j].size() || !std::isfinite(deviation_by_run[j][k])) continue;
      double pred;
      if (degree >= 0) {
        pred = EvaluatePolynomial(coeff, (x[k] - center_mm) / half_span_mm);
      } else {  // the table of the other runs' means, linear between its points, ends held
        const auto it = std::lower_bound(xs.begin(), xs.end(), x[k]);
        if (it == xs.begin()) pred = means.front();
        else if (it == xs.end()) pred = means.back();
        else {
          const std::size_t hi = static_cast<std::size_t>(it - xs.begin()), lo = hi - 1;
          const double t = (x[k] - xs[lo]) / (xs[hi] - xs[lo]);
          pred = means[lo] + t * (means[hi] - means[lo]);
        }
      }
      ss += std::pow(deviation_by_run[j][k] - pred, 2);
      ++count;
    }
  }
  return count ? std::sqrt(ss / static_cast<double>(count)) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace trueaxis::model
