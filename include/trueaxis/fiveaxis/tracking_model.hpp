#pragma once
// Seed 004's servo tracking-error model (docs/fiveaxis.md, "Tracking-error
// model"). For a P position loop with velocity feed-forward kf over a PI
// velocity loop driving inertia with viscous friction, the tracking error
// e = r − y of each axis, expanded at low frequency, is
//     e ≈ c_v·v + c_a·a + c_j·j      (v, a, j: velocity, acceleration, jerk of the command)
// with c_v = (1 − kf)/Kp, and c_a, c_j combining Kp, Kv, Ti, kt, the motor +
// screw inertia j and friction b, the load m and c and the transmission —
// all linear in kf. The model keeps the three lumped coefficients at kf = 0
// and at kf = 1 (what an axis test can identify); any kf in between is the
// linear blend.
#include <array>
#include <string>
#include <vector>

#include "trueaxis/fiveaxis/kinematics.hpp"

namespace trueaxis::fiveaxis {

struct AxisErrorModel {
  std::array<double, 3> without_ff{};  // c_v (s), c_a (s²), c_j (s³) at kf = 0
  std::array<double, 3> full_ff{};     // at kf = 1
  double fit_rms = 0;                  // identification residual (mm or deg)
  double signal_rms = 0;               // rms tracking error of the identification runs
  std::array<double, 3> At(double kf) const;
};

struct TrackingErrorModel {
  std::array<AxisErrorModel, kAxisCount> axes;
  double derivative_window_s = 0.01;  // Savitzky–Golay window of v, a, j
};

// Velocity, acceleration and jerk of a sampled signal: a cubic
// Savitzky–Golay fit over ±half_window samples (ends held).
struct Derivatives {
  std::vector<double> v, a, j;
};
Derivatives SavitzkyGolay(const std::vector<double>& x, double dt_s, int half_window);
int HalfWindowSamples(double window_s, double dt_s);

// Predicted tracking error of each axis for joint commands at kf.
std::vector<AxisVector> PredictTrackingError(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                             double dt_s, double kf);

// Seed 004's feed-forward coefficient: per moving axis the kf that minimises
// the model's tracking error over that axis's reference command (e is linear
// in kf, so a closed form), then the mean over the axes.
struct FeedForwardChoice {
  std::array<double, kAxisCount> per_axis{};  // NaN for an axis that does not move
  double averaged = 0;
};
FeedForwardChoice ChooseFeedForward(const TrackingErrorModel& model, const std::vector<AxisVector>& command, double dt_s);

std::string ModelToJson(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names);
// InputError naming the source for a malformed model.
TrackingErrorModel ModelFromJson(const std::string& text, const std::string& source);

}  // namespace trueaxis::fiveaxis
