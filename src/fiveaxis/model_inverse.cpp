// The tracking-error model's inverse by one division per frequency.
#include "trueaxis/fiveaxis/model_inverse.hpp"

#include <complex>

#include <unsupported/Eigen/FFT>

namespace trueaxis::fiveaxis {
namespace {

// The terms that act on the command linearly (v, a, j and the filters of a); the
// others are the friction's, fixed by the programmed direction of motion.
bool IsLinearTerm(int t) {
  return t < kSeedTerms + kLagTerms || (t >= kModelTermsWithoutMode && t < kModelTermsWithoutMode + kModeTerms);
}

}  // namespace

std::vector<AxisVector> InvertTrackingModel(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                            double dt_s, double kf, double regularisation) {
  const std::size_t n = command.size();
  std::vector<AxisVector> out = command;
  if (n == 0 || !model.with_extensions) return out;
  const int half_window = HalfWindowSamples(model.derivative_window_s, dt_s);
  // Room for the inverse's response on both sides of the moves (circular convolution).
  std::size_t size = 1;
  while (size < 2 * n + 8 * static_cast<std::size_t>(half_window) + 4096) size *= 2;
  const std::vector<AxisVector> error = PredictTrackingError(model, command, dt_s, kf);
  Eigen::FFT<double> fft;
  std::vector<double> impulse(size, 0.0), response(size), g(size), d;
  std::vector<std::complex<double>> h_spectrum, g_spectrum;
  for (int a = 0; a < kAxisCount; ++a) {
    const AxisErrorModel& ax = model.axes[a];
    // Impulse response of the linear terms: the Savitzky–Golay derivatives reach
    // half_window samples back, so the impulse sits there and the response is
    // shifted back to time zero (circularly: its non-causal part wraps to the end).
    std::fill(impulse.begin(), impulse.end(), 0.0);
    impulse[static_cast<std::size_t>(half_window)] = 1.0;
    const auto r = ModelRegressors(impulse, dt_s, model.derivative_window_s, ax.friction_band, ax.mode);
    const ModelCoefficients c = ax.At(kf);
    std::fill(response.begin(), response.end(), 0.0);
    for (int t = 0; t < kModelTerms; ++t) {
      if (!IsLinearTerm(t) || r[t].size() != size || c[t] == 0) continue;
      for (std::size_t i = 0; i < size; ++i) response[(i + size - static_cast<std::size_t>(half_window)) % size] += c[t] * r[t][i];
    }
    std::fill(g.begin(), g.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) g[i] = error[i][a];
    fft.fwd(h_spectrum, response);
    fft.fwd(g_spectrum, g);
    for (std::size_t k = 0; k < g_spectrum.size(); ++k) {
      const std::complex<double> t = 1.0 - h_spectrum[k];
      g_spectrum[k] *= std::conj(t) / (std::norm(t) + regularisation * regularisation);
    }
    fft.inv(d, g_spectrum);
    for (std::size_t i = 0; i < n; ++i) out[i][a] += d[i];
  }
  return out;
}

}  // namespace trueaxis::fiveaxis
