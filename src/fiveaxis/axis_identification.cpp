// Axis sine tests and the least-squares fit of seed 004's coefficients.
#include "trueaxis/fiveaxis/axis_identification.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Dense>

#include "trueaxis/fiveaxis/servo_drive.hpp"

namespace trueaxis::fiveaxis {

std::vector<double> AxisTestCommand(const DriveParams& d, double servo_rate_hz, const AxisTestOptions& o) {
  const double dt = 1.0 / servo_rate_hz;
  std::vector<double> r;
  auto rest = [&] {
    for (int i = 0; i < static_cast<int>(o.rest_s / dt); ++i) r.push_back(0.0);
  };
  rest();
  {
    const double w = 2 * std::numbers::pi * o.slow_frequency_hz;
    const int n = static_cast<int>(std::lround(o.periods / o.slow_frequency_hz / dt));
    for (int i = 0; i < n; ++i) r.push_back(o.slow_peak_velocity / w * (1 - std::cos(w * i * dt)));
    rest();
  }
  for (double f : o.frequencies_hz) {
    const double w = 2 * std::numbers::pi * f;
    // Peak velocity of A(1 − cos wt) is A·w.
    const double amplitude = std::min({o.max_amplitude, o.velocity_fraction * d.max_velocity_per_s / w,
                                       o.max_acceleration / (w * w)});
    const int n = static_cast<int>(std::lround(o.periods / f / dt));
    for (int i = 0; i < n; ++i) r.push_back(amplitude * (1 - std::cos(w * i * dt)));
    rest();
  }
  return r;
}

namespace {

// Least squares through the normal equations of scaled columns (v, a, j differ by decades); the
// complete orthogonal decomposition copes with nearly collinear terms. rms: the residual's, from
// the normal equations (ee = e·e over `rows` rows).
Eigen::VectorXd SolveNormalEquations(const Eigen::MatrixXd& gram, const Eigen::VectorXd& rhs, double ee,
                                     Eigen::Index rows, double* rms) {
  const Eigen::VectorXd scale = gram.diagonal().cwiseMax(1e-300).cwiseSqrt();
  const Eigen::MatrixXd scaled = scale.cwiseInverse().asDiagonal() * gram * scale.cwiseInverse().asDiagonal();
  const Eigen::VectorXd c = scaled.completeOrthogonalDecomposition().solve(rhs.cwiseQuotient(scale)).cwiseQuotient(scale);
  if (rms) *rms = std::sqrt(std::max(0.0, ee - 2 * c.dot(rhs) + c.dot(gram * c)) / std::max<Eigen::Index>(1, rows));
  return c;
}

}  // namespace

ModelCoefficients FitTrackingCoefficients(const AxisTrace& trace, double dt_s, double window_s, bool with_extensions,
                                          double friction_band, const DriveMode& mode, double* fit_rms,
                                          double* signal_rms) {
  // Friction acts on the motion of the axis, so its direction comes from the measured position.
  const auto r = ModelRegressors(trace.command, dt_s, window_s, friction_band, mode, &trace.measured);
  const int terms = !with_extensions ? kSeedTerms : mode.present() ? kModelTerms : kModelTermsWithoutMode;
  const Eigen::Index n = static_cast<Eigen::Index>(trace.command.size());
  Eigen::MatrixXd x(n, terms);
  Eigen::VectorXd e(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int t = 0; t < terms; ++t) x(i, t) = r[t][i];
    e(i) = trace.command[i] - trace.measured[i];
  }
  const Eigen::VectorXd c = SolveNormalEquations(x.transpose() * x, x.transpose() * e, e.squaredNorm(), n, nullptr);
  if (fit_rms) *fit_rms = std::sqrt((e - x * c).squaredNorm() / std::max<Eigen::Index>(1, n));
  if (signal_rms) *signal_rms = std::sqrt(e.squaredNorm() / std::max<Eigen::Index>(1, n));
  ModelCoefficients out{};
  for (int t = 0; t < terms; ++t) out[t] = c(t);
  return out;
}

DriveMode FindDriveMode(const AxisTrace& trace, double dt_s, double friction_band, const AxisTestOptions& o) {
  // The model's other terms are the same for every candidate: their normal equations are formed once,
  // each candidate adds its Kautz columns. Every stride-th row (at most ~30 000) keeps the search cheap.
  const auto r = ModelRegressors(trace.command, dt_s, o.derivative_window_s, friction_band, DriveMode{}, &trace.measured);
  const std::vector<double> sign = DirectionOfMotion(trace.measured, dt_s, o.derivative_window_s, friction_band);
  const std::size_t n = trace.command.size(), stride = std::max<std::size_t>(1, (n + 29999) / 30000);
  const Eigen::Index rows = static_cast<Eigen::Index>((n + stride - 1) / stride);
  constexpr int kBase = kModelTermsWithoutMode, kMode = kModeTerms + kModeFrictionTerms;
  Eigen::MatrixXd base(rows, kBase);
  Eigen::VectorXd e(rows);
  for (Eigen::Index k = 0; k < rows; ++k) {
    const std::size_t i = static_cast<std::size_t>(k) * stride;
    for (int t = 0; t < kBase; ++t) base(k, t) = r[t][i];
    e(k) = trace.command[i] - trace.measured[i];
  }
  Eigen::MatrixXd gram(kBase + kMode, kBase + kMode);
  Eigen::VectorXd rhs(kBase + kMode);
  gram.topLeftCorner(kBase, kBase) = base.transpose() * base;
  rhs.head(kBase) = base.transpose() * e;
  const double ee = e.squaredNorm();
  double without_mode = 0;
  SolveNormalEquations(gram.topLeftCorner(kBase, kBase), rhs.head(kBase), ee, rows, &without_mode);

  std::array<std::vector<double>, kMode> filtered;
  Eigen::MatrixXd columns(rows, kMode);
  auto residual = [&](const DriveMode& mode) {
    KautzBank(r[1], dt_s, mode, kModeTerms, &filtered[0]);
    KautzBank(sign, dt_s, mode, kModeFrictionTerms, &filtered[kModeTerms]);
    for (Eigen::Index k = 0; k < rows; ++k)
      for (int t = 0; t < kMode; ++t) columns(k, t) = filtered[t][static_cast<std::size_t>(k) * stride];
    gram.topRightCorner(kBase, kMode) = base.transpose() * columns;
    gram.bottomLeftCorner(kMode, kBase) = gram.topRightCorner(kBase, kMode).transpose();
    gram.bottomRightCorner(kMode, kMode) = columns.transpose() * columns;
    rhs.tail(kMode) = columns.transpose() * e;
    double rms = 0;
    SolveNormalEquations(gram, rhs, ee, rows, &rms);
    return rms;
  };
  const double max_hz = std::min(200.0, 1.0 / dt_s / 8);
  DriveMode best;
  double best_rms = INFINITY;
  auto consider = [&](DriveMode mode) {
    mode.damping = std::clamp(mode.damping, 0.01, 1.0);
    mode.frequency_hz = std::clamp(mode.frequency_hz, o.mode_min_hz, max_hz);
    const double rms = residual(mode);
    if (rms < best_rms) {
      best_rms = rms;
      best = mode;
      return true;
    }
    return false;
  };
  for (double f = o.mode_min_hz; f <= max_hz; f *= o.mode_grid_ratio)
    for (double zeta : o.mode_dampings) consider({f, zeta});
  // Refine: a pattern search in (log f, log ζ), the steps halved (in the log) until fine.
  double f_step = o.mode_grid_ratio, z_step = 1.5;
  for (int level = 0; level < 5; ++level) {
    for (bool moved = true; moved;) {
      const DriveMode at = best;
      moved = consider({at.frequency_hz * f_step, at.damping}) || consider({at.frequency_hz / f_step, at.damping}) ||
              consider({at.frequency_hz, at.damping * z_step}) || consider({at.frequency_hz, at.damping / z_step});
    }
    f_step = std::sqrt(f_step);
    z_step = std::sqrt(z_step);
  }
  if (!(best_rms < (1 - o.mode_min_gain) * without_mode)) return DriveMode{};
  return best;
}

TrackingErrorModel IdentifyTrackingModel(const FiveAxisMachine& m, const AxisTestOptions& o, const AxisTestRunner& run) {
  TrackingErrorModel model;
  model.derivative_window_s = o.derivative_window_s;
  model.with_extensions = o.with_extensions;
  const double dt = 1.0 / m.servo_rate_hz;
  for (int a = 0; a < kAxisCount; ++a) {
    const std::vector<double> command = AxisTestCommand(m.drives[a], m.servo_rate_hz, o);
    const AxisTrace without{command, run(a, 0.0, command)}, full{command, run(a, 1.0, command)};
    auto& ax = model.axes[a];
    // The friction band that explains the feed-forward run best — the regime the
    // correction works in (without extensions it plays no part): the best of the
    // candidates, then a golden-section search (in log band) between its neighbours,
    // since the fit is sensitive to it (head example, X: 2.3 % at the best candidate,
    // 0.3 % at the refined band).
    auto choose_band = [&](const DriveMode& mode) {
      const std::vector<double>& bands = o.friction_bands;
      double band = ax.friction_band;
      if (o.with_extensions && !bands.empty()) {
        auto residual = [&](double log_band) {
          double rms = 0;
          FitTrackingCoefficients(full, dt, o.derivative_window_s, true, std::exp(log_band), mode, &rms, nullptr);
          return rms;
        };
        std::size_t best = 0;
        std::vector<double> rms(bands.size());
        for (std::size_t i = 0; i < bands.size(); ++i)
          if ((rms[i] = residual(std::log(bands[i]))) < rms[best]) best = i;
        double lo = std::log(bands[best > 0 ? best - 1 : best]), hi = std::log(bands[std::min(best + 1, bands.size() - 1)]);
        double best_log = std::log(bands[best]), best_rms = rms[best];
        const double golden = (std::sqrt(5.0) - 1) / 2;
        double x1 = hi - golden * (hi - lo), x2 = lo + golden * (hi - lo);
        double f1 = residual(x1), f2 = residual(x2);
        for (int k = 0; k < o.friction_band_refinements && hi - lo > 1e-3; ++k) {
          if (f1 < f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - golden * (hi - lo), f1 = residual(x1);
          } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + golden * (hi - lo), f2 = residual(x2);
          }
        }
        for (const auto& [x, f] : {std::pair{x1, f1}, std::pair{x2, f2}})
          if (f < best_rms) best_rms = f, best_log = x;
        band = std::exp(best_log);
      }
      ax.without_ff = FitTrackingCoefficients(without, dt, o.derivative_window_s, o.with_extensions, band, mode, nullptr, nullptr);
      ax.full_ff = FitTrackingCoefficients(full, dt, o.derivative_window_s, o.with_extensions, band, mode, &ax.fit_rms,
                                           &ax.signal_rms);
      ax.friction_band = band;
      ax.mode = mode;
    };
    choose_band(DriveMode{});
    // A slow drive mode the other terms do not span: searched on the feed-forward run, then the band again with it.
    if (o.with_extensions && o.search_mode) {
      const DriveMode mode = FindDriveMode(full, dt, ax.friction_band, o);
      if (mode.present()) choose_band(mode);
    }
  }
  return model;
}

AxisTestRunner VirtualMachineRunner(const FiveAxisMachine& m) {
  return [m](int axis, double kf, const std::vector<double>& command) {
    return RunDrive(m.drives[axis], m.servo_rate_hz, FeedForward{kf, 0.0}, command);
  };
}

}  // namespace trueaxis::fiveaxis
