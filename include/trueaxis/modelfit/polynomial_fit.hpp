#pragma once
// Least-squares polynomials of position and the automatic choice of their
// degree (seed 000: "拟合次数可以根据定位误差曲线形状动态调整").
//
// Coordinates are normalised, u = (x − center) / half_span ∈ [−1, 1], so the
// Vandermonde matrix stays well conditioned up to degree ~10; the solve is
// Eigen's column-pivoting Householder QR (never the normal equations).
//
// Degree rule (SelectPolynomialDegree), stated once here and in
// docs/model-file.md:
//   1. For every degree d = 1 … min(max_degree, n − 2), the leave-one-target-out
//      cross-validation error CV(d): fit the n − 1 other target means, predict
//      the left-out one (this is interpolation between measured targets, and
//      extrapolation at the two ends — exactly what compensation needs).
//   2. noise = the standard error of the target means from the run-to-run
//      scatter (pooled s / √runs); unknown with one run.
//   3. Choose the SMALLEST d with CV(d)² ≤ CV_min² + noise² and CV(d) ≤ 1.05·CV_min
//      when the noise is unknown: a higher degree must beat a lower one by
//      more than the measurements can resolve.
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace trueaxis::model {

// Coefficients c_0 … c_degree (ascending powers of u) minimising Σ (y − Σ c_j u^j)².
// Requires u.size() == y.size() > degree; throws std::invalid_argument otherwise.
std::vector<double> FitPolynomial(std::span<const double> u, std::span<const double> y, int degree);
double EvaluatePolynomial(std::span<const double> coefficients, double u);

struct DegreeCandidate {
  int degree = 0;
  double fit_rms_um = 0;  // RMS residual of the fit to all target means
  double cv_rms_um = std::numeric_limits<double>::quiet_NaN();  // leave-one-target-out
};

struct DegreeSelection {
  int degree = 1;
  std::vector<DegreeCandidate> candidates;
  double noise_um = std::numeric_limits<double>::quiet_NaN();     // standard error of a target mean
  double threshold_um = std::numeric_limits<double>::quiet_NaN(); // CV accepted up to this
  std::string rule;  // the sentence explaining the choice, for reports
};

// x: distinct target positions; y: mean error at each. center/half_span: the
// normalisation. noise_um: standard error of the means (NaN if unknown).
DegreeSelection SelectPolynomialDegree(std::span<const double> x, std::span<const double> y, double center_mm,
                                       double half_span_mm, int max_degree, double noise_um);

// Leave-one-target-out CV RMS of the seed-002 table (linear interpolation,
// end values held), for comparison with the polynomial.
double TableCrossValidationRms(std::span<const double> x, std::span<const double> y);

// Leave-one-RUN-out CV RMS (µm) of Er(x) at the targets x: for each run j, Er(x) is fitted to the
// per-target means of the OTHER runs — as the seed-002 table (degree < 0: the means themselves)
// or as a polynomial of `degree` in u = (x − center)/half_span — and predicts run j's deviations.
// A repeatable short-wavelength error is in every run, so the table predicts it in a held-out
// run; noise is not, so fitting it costs the table here. `deviation_by_run[j][k]` is run j at
// target k (NaN: not measured). NaN with fewer than 3 runs (2 to fit, 1 to test).
double LeaveOneRunOutRms(std::span<const double> x, const std::vector<std::vector<double>>& deviation_by_run,
                         int degree, double center_mm, double half_span_mm);

}  // namespace trueaxis::model
