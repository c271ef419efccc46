// Command correction through the kinematics (seed 004).
#include "trueaxis/fiveaxis/command_correction.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include <unsupported/Eigen/FFT>

namespace trueaxis::fiveaxis {
namespace {

constexpr double kStepWindowS = 0.03;  // windows of the step fraction (s)
constexpr double kInverseKernelS = 1.0;  // the model's impulse response is taken over ±this (s)
constexpr double kInversePaddingS = 2.0; // zeros after the command, so the inverse's tails do not wrap round (s)

// The end points are constraints: over the second half of the final rest (the
// samples equal to the last command) the correction fades out with a raised
// cosine, so the corrected command stands exactly on the programmed end.
// ExtendRestUntilSettled makes that rest long enough for the correction to
// have decayed before it fades. Likewise over the first half of the rest
// before the first move the correction fades in (the model's inverse starts
// a little before the motion), so the corrected program starts where the
// programmed one starts.
void FadeAtTheEnds(const std::vector<AxisVector>& command, std::vector<AxisVector>& corrected) {
  const std::size_t n = command.size();
  if (n < 2) return;
  auto fade = [&](std::size_t rest, auto index) {
    const std::size_t samples = std::max<std::size_t>(1, rest / 2);
    for (std::size_t k = 0; k <= samples && k < n; ++k) {
      const std::size_t i = index(k);  // k samples from the end point
      const double keep = 0.5 * (1.0 - std::cos(std::numbers::pi * static_cast<double>(k) / static_cast<double>(samples)));
      for (int a = 0; a < kAxisCount; ++a) corrected[i][a] = command[i][a] + keep * (corrected[i][a] - command[i][a]);
    }
  };
  std::size_t rest_start = n - 1;
  while (rest_start > 0 && command[rest_start - 1] == command.back()) --rest_start;
  fade(n - 1 - rest_start, [n](std::size_t k) { return n - 1 - k; });
  std::size_t first_move = 0;
  while (first_move + 1 < n && command[first_move + 1] == command.front()) ++first_move;
  fade(first_move, [](std::size_t k) { return k; });
}

}  // namespace

std::vector<AxisVector> CorrectCommands(const Kinematics& kin, const TrackingErrorModel& model,
                                        const std::vector<AxisVector>& command, double dt_s, double kf, int iterations,
                                        double update_filter_s) {
  const std::size_t n = command.size();
  std::vector<Eigen::Vector3d> target_tip(n);
  for (std::size_t i = 0; i < n; ++i) target_tip[i] = kin.Forward(command[i]).tip_mm;
  std::vector<AxisVector> corrected = command;
  // Per servo period: tip x, y, z, tilt, rot — the virtual target (state), the
  // predicted residual of the current command, and of the one before the last step.
  using Five = std::array<double, 5>;
  std::vector<Five> state(n), residual(n), previous_residual(n), step(n);
  for (std::size_t i = 0; i < n; ++i)
    state[i] = {target_tip[i].x(), target_tip[i].y(), target_tip[i].z(), command[i][kTilt], command[i][kRot]};
  auto apply_state = [&] {
    for (std::size_t i = 0; i < n; ++i)
      corrected[i] = kin.Inverse(Eigen::Vector3d(state[i][0], state[i][1], state[i][2]), state[i][3], state[i][4]);
  };
  for (int it = 0; it <= iterations; ++it) {
    // The friction's direction of motion stays the programmed one: a tiny
    // correction must not flip it at a reversal.
    const std::vector<AxisVector> error = PredictTrackingError(model, corrected, dt_s, kf, &command);
    for (std::size_t i = 0; i < n; ++i) {
      AxisVector predicted_actual;
      for (int a = 0; a < kAxisCount; ++a) predicted_actual[a] = corrected[i][a] - error[i][a];
      const Eigen::Vector3d tip_error = kin.Forward(predicted_actual).tip_mm - target_tip[i];
      residual[i] = {tip_error.x(), tip_error.y(), tip_error.z(), predicted_actual[kTilt] - command[i][kTilt],
                     predicted_actual[kRot] - command[i][kRot]};
    }
    // Step length: the predicted residual is affine in the step (the model is
    // linear for the programmed direction of motion), so per component and per
    // window of kStepWindowS the fraction 0 … 1 of the last step that leaves
    // the least residual follows from the residuals before and after it
    // (linear between the windows' centres, so the command stays smooth).
    // Where the drive rings the plain update would diverge; per window, the
    // passes still converge fully elsewhere (docs/fiveaxis.md, "Correction").
    if (it > 0) {
      bool shortened = false;
      const std::size_t window = std::max<std::size_t>(2, static_cast<std::size_t>(std::lround(kStepWindowS / dt_s)));
      const std::size_t windows = (n + window - 1) / window;
      std::vector<double> best(windows);
      for (int c = 0; c < 5; ++c) {
        for (std::size_t w = 0; w < windows; ++w) {
          double num = 0, den = 0;
          for (std::size_t i = w * window; i < std::min(n, (w + 1) * window); ++i) {
            const double change = residual[i][c] - previous_residual[i][c];
            num -= previous_residual[i][c] * change;
            den += change * change;
          }
          best[w] = den > 0 ? std::clamp(num / den, 0.0, 1.0) : 1.0;
        }
        for (std::size_t i = 0; i < n; ++i) {
          // Linear between the windows' centres.
          const double pos = (static_cast<double>(i) + 0.5) / static_cast<double>(window) - 0.5;
          const std::size_t w0 = static_cast<std::size_t>(std::clamp(std::floor(pos), 0.0, static_cast<double>(windows - 1)));
          const std::size_t w1 = std::min(windows - 1, w0 + 1);
          const double t = std::clamp(pos - static_cast<double>(w0), 0.0, 1.0);
          const double fraction = best[w0] + t * (best[w1] - best[w0]);
          if (fraction >= 1.0) continue;
          shortened = true;
          state[i][c] -= (1.0 - fraction) * step[i][c];
          residual[i][c] = previous_residual[i][c] + fraction * (residual[i][c] - previous_residual[i][c]);
        }
      }
      if (shortened) apply_state();
    }
    if (it == iterations) break;
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 5; ++c) step[i][c] = -residual[i][c];
    // Passes after the first: the update through a zero-phase low-pass (a
    // forward and a backward first-order lag), so the passes converge where
    // the model is right and leave alone what the drive cannot follow.
    if (it > 0 && update_filter_s > 0) {
      const double alpha = 1.0 - std::exp(-dt_s / update_filter_s);
      for (int c = 0; c < 5; ++c) {
        double low = 0;
        for (std::size_t i = 0; i < n; ++i) step[i][c] = low += alpha * (step[i][c] - low);
        low = 0;
        for (std::size_t i = n; i-- > 0;) step[i][c] = low += alpha * (step[i][c] - low);
      }
    }
    previous_residual = residual;
    for (std::size_t i = 0; i < n; ++i)
      for (int c = 0; c < 5; ++c) state[i][c] += step[i][c];
    apply_state();
  }
  FadeAtTheEnds(command, corrected);
  return corrected;
}

std::vector<AxisVector> InvertTrackingModel(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                            double dt_s, double kf, double regularization) {
  const std::size_t n = command.size();
  if (n < 2) return command;
  // The model is linear in the command once the friction's direction of motion
  // is held at the programmed one: predicted actual(q + Δ) = q − e(q) + Δ − L(Δ),
  // with L the model's terms without the friction. So the correction solves
  // Δ − L(Δ) = e(q) — a convolution, inverted per axis in the frequency domain
  // with Tikhonov regularisation (the gain stays below 1 / (2·regularization)
  // where the model says the drive cannot follow).
  const std::size_t half = static_cast<std::size_t>(std::lround(kInverseKernelS / dt_s));
  std::size_t size = 1;
  while (size < n + static_cast<std::size_t>(std::lround(kInversePaddingS / dt_s))) size *= 2;
  std::vector<AxisVector> impulse(2 * half + 1, AxisVector{}), still(2 * half + 1, AxisVector{});
  for (int a = 0; a < kAxisCount; ++a) impulse[half][a] = 1.0;
  const std::vector<AxisVector> response = PredictTrackingError(model, impulse, dt_s, kf, &still);
  const std::vector<AxisVector> error = PredictTrackingError(model, command, dt_s, kf);
  Eigen::FFT<double> fft;
  std::vector<double> kernel(size), rhs(size), delta;
  std::vector<std::complex<double>> kernel_f, rhs_f;
  std::vector<AxisVector> corrected = command;
  for (int a = 0; a < kAxisCount; ++a) {
    // Impulse response of command → predicted actual, centred on sample 0 (circular).
    std::fill(kernel.begin(), kernel.end(), 0.0);
    for (std::size_t k = 0; k <= 2 * half; ++k)
      kernel[(k + size - half) % size] += impulse[k][a] - response[k][a];
    std::fill(rhs.begin(), rhs.end(), 0.0);
    for (std::size_t i = 0; i < n; ++i) rhs[i] = error[i][a];
    fft.fwd(kernel_f, kernel);
    fft.fwd(rhs_f, rhs);
    for (std::size_t k = 0; k < rhs_f.size(); ++k)
      rhs_f[k] *= std::conj(kernel_f[k]) / (std::norm(kernel_f[k]) + regularization * regularization);
    fft.inv(delta, rhs_f);
    for (std::size_t i = 0; i < n; ++i) corrected[i][a] += delta[i];
  }
  FadeAtTheEnds(command, corrected);
  return corrected;
}

double ExtendRestUntilSettled(std::vector<AxisVector>& joints, const TrackingErrorModel& model, double dt_s, double kf,
                              double settle_tolerance, double max_extra_s) {
  if (joints.empty()) return 0;
  const std::size_t chunk = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(0.05 / dt_s)));
  const std::size_t max_extra = static_cast<std::size_t>(std::lround(max_extra_s / dt_s));
  std::size_t added = 0;
  while (true) {
    // The error over the last chunk: a Laguerre transient may cross zero, so one sample is not enough.
    const std::vector<AxisVector> error = PredictTrackingError(model, joints, dt_s, kf);
    double worst = 0;
    for (std::size_t i = error.size() - std::min(error.size(), chunk); i < error.size(); ++i)
      for (double e : error[i]) worst = std::max(worst, std::abs(e));
    if (worst <= settle_tolerance || added >= max_extra) break;
    joints.insert(joints.end(), chunk, joints.back());
    added += chunk;
  }
  return static_cast<double>(added) * dt_s;
}

ToolPath CommandsToProgram(const std::vector<AxisVector>& joints, const Kinematics& kin, double dt_s,
                           int samples_per_block, const std::string& name) {
  ToolPath path;
  path.name = name;
  const std::size_t step = static_cast<std::size_t>(std::max(1, samples_per_block));
  std::size_t previous = 0;
  // Samples 0, step, 2·step, …, and the last one; each block lasts the samples since the previous.
  for (std::size_t k = 0; k < joints.size();) {
    PathVertex v;
    v.tip_mm = kin.Forward(joints[k]).tip_mm;
    v.tilt_deg = joints[k][kTilt];
    v.rot_deg = joints[k][kRot];
    v.move = k == 0 ? MoveKind::kStart : MoveKind::kInverseTime;
    v.duration_s = static_cast<double>(k - previous) * dt_s;
    path.vertices.push_back(v);
    previous = k;
    if (k + 1 == joints.size()) break;
    k = std::min(k + step, joints.size() - 1);
  }
  return path;
}

}  // namespace trueaxis::fiveaxis
