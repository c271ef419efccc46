// Axis sine tests and the least-squares fit of seed 004's coefficients.
#include "trueaxis/fiveaxis/axis_identification.hpp"

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

ModelCoefficients FitTrackingCoefficients(const AxisTrace& trace, double dt_s, double window_s, bool with_extensions,
                                          double friction_band, double* fit_rms, double* signal_rms) {
  // Friction acts on the motion of the axis, so its direction comes from the measured position.
  const auto r = ModelRegressors(trace.command, dt_s, window_s, friction_band, &trace.measured);
  const int terms = with_extensions ? kModelTerms : kSeedTerms;
  const Eigen::Index n = static_cast<Eigen::Index>(trace.command.size());
  Eigen::MatrixXd x(n, terms);
  Eigen::VectorXd e(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int t = 0; t < terms; ++t) x(i, t) = r[t][i];
    e(i) = trace.command[i] - trace.measured[i];
  }
  // Column scaling keeps the problem well conditioned (v, a, j differ by decades).
  Eigen::VectorXd scale(terms);
  for (int c = 0; c < terms; ++c) scale(c) = std::max(1e-300, x.col(c).norm());
  const Eigen::MatrixXd xs = x * scale.cwiseInverse().asDiagonal();
  // Normal equations of the scaled columns (small, terms × terms); the
  // complete orthogonal decomposition copes with nearly collinear terms.
  const Eigen::MatrixXd gram = xs.transpose() * xs;
  const Eigen::VectorXd c = gram.completeOrthogonalDecomposition().solve(xs.transpose() * e).cwiseQuotient(scale);
  if (fit_rms) *fit_rms = std::sqrt((e - x * c).squaredNorm() / std::max<Eigen::Index>(1, n));
  if (signal_rms) *signal_rms = std::sqrt(e.squaredNorm() / std::max<Eigen::Index>(1, n));
  ModelCoefficients out{};
  for (int t = 0; t < terms; ++t) out[t] = c(t);
  return out;
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
    double best = INFINITY;
    // The friction band that explains the feed-forward run best — the regime the
    // correction works in (without extensions it plays no part).
    const std::vector<double> bands = o.with_extensions ? o.friction_bands : std::vector<double>{ax.friction_band};
    for (double band : bands) {
      double rms0 = 0, rms1 = 0, signal1 = 0;
      const auto c0 = FitTrackingCoefficients(without, dt, o.derivative_window_s, o.with_extensions, band, &rms0, nullptr);
      const auto c1 = FitTrackingCoefficients(full, dt, o.derivative_window_s, o.with_extensions, band, &rms1, &signal1);
      if (rms1 < best) {
        best = rms1;
        ax.without_ff = c0;
        ax.full_ff = c1;
        ax.friction_band = band;
        ax.fit_rms = rms1;
        ax.signal_rms = signal1;
      }
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
