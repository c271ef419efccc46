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
//
// Extensions (not in seed 004), switched off by `with_extensions = false`:
// 10 discrete Laguerre filters (pole 10 ms) of the acceleration — the error's
// own dynamics (lags and ringing) after a change of acceleration, which the
// truncated v/a/j series misses — and 8 Laguerre filters of the direction of
// motion s = tanh(v / band) for Coulomb friction: a PI velocity loop cancels a
// constant friction force, but each reversal leaves a transient. The band
// (how sharply friction turns over at a reversal) is chosen per axis by the
// identification.
//
// Slow drive mode (not in seed 004): a heavy load on a slow velocity loop gives
// the tracking error a lightly damped pole pair (e.g. 20 Hz, damping 0.15,
// decaying over 50 ms) that 10 Laguerre filters with a 10 ms pole cannot span.
// The identification searches that pair in its own traces (DriveMode) and the
// model adds 4 Kautz filters (the orthonormal filters of one pole pair) of the
// acceleration and 4 of the direction of motion at it. An axis without such a
// mode (frequency 0) has these terms zero.
#include <array>
#include <string>
#include <vector>

#include "trueaxis/fiveaxis/kinematics.hpp"

namespace trueaxis::fiveaxis {

inline constexpr int kSeedTerms = 3;     // v, a, j
inline constexpr int kLagTerms = 10;     // Laguerre filters of a
inline constexpr int kFrictionTerms = 8; // Laguerre filters of s = tanh(v / band)
inline constexpr int kModeTerms = 4;     // Kautz filters of a at the drive mode
inline constexpr int kModeFrictionTerms = 4;  // Kautz filters of s at the drive mode
// Model files written before the drive mode hold this many coefficients per run.
inline constexpr int kModelTermsWithoutMode = kSeedTerms + kLagTerms + kFrictionTerms;
inline constexpr int kModelTerms = kModelTermsWithoutMode + kModeTerms + kModeFrictionTerms;
inline constexpr double kLaguerreTimeConstantS = 0.01;  // pole of the Laguerre filters
using ModelCoefficients = std::array<double, kModelTerms>;

// A pole pair of an axis's tracking error, s = 2πf·(−ζ ± i·√(1 − ζ²)); damping 1 is a double real pole.
struct DriveMode {
  double frequency_hz = 0;  // 0 = none
  double damping = 0;       // 0 < ζ ≤ 1
  bool present() const { return frequency_hz > 0; }
};

struct AxisErrorModel {
  ModelCoefficients without_ff{};  // c_v (s), c_a (s²), c_j (s³), lag and friction terms at kf = 0
  ModelCoefficients full_ff{};     // at kf = 1
  double fit_rms = 0;              // identification residual at kf = 1 (mm or deg)
  double signal_rms = 0;           // rms tracking error of that identification run
  double friction_band = 0.1;      // mm/s or deg/s
  DriveMode mode;                  // slow drive mode (none: the last kModeTerms + kModeFrictionTerms terms are 0)
  ModelCoefficients At(double kf) const;
};

struct TrackingErrorModel {
  std::array<AxisErrorModel, kAxisCount> axes;
  double derivative_window_s = 0.01;  // Savitzky–Golay window of v, a, j
  bool with_extensions = true;
};

// Velocity, acceleration and jerk of a sampled signal: a cubic
// Savitzky–Golay fit over ±half_window samples (ends held).
struct Derivatives {
  std::vector<double> v, a, j;
};
Derivatives SavitzkyGolay(const std::vector<double>& x, double dt_s, int half_window);
int HalfWindowSamples(double window_s, double dt_s);

// The model's regressors of one axis command: v, a, j, the lagged accelerations, the friction transients,
// and (when `mode` is present) the acceleration and the direction of motion filtered at the drive mode
// (else those terms are empty vectors).
// `direction_from` (same length), when given, supplies the direction of
// motion instead of `command` (the correction keeps the programmed one).
std::array<std::vector<double>, kModelTerms> ModelRegressors(const std::vector<double>& command, double dt_s,
                                                             double derivative_window_s, double friction_band,
                                                             const DriveMode& mode,
                                                             const std::vector<double>* direction_from = nullptr);
// Direction of motion of a sampled position: tanh(v / friction_band), v its Savitzky–Golay velocity.
std::vector<double> DirectionOfMotion(const std::vector<double>& position, double dt_s, double derivative_window_s,
                                      double friction_band);
// The `count` (even) Kautz filters of one pole pair driven by x, into out[0] … out[count − 1].
void KautzBank(const std::vector<double>& x, double dt_s, const DriveMode& mode, int count,
               std::vector<double>* out);

// Predicted tracking error of each axis for joint commands at kf.
std::vector<AxisVector> PredictTrackingError(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                             double dt_s, double kf,
                                             const std::vector<AxisVector>* direction_from = nullptr);
// Seed 004's feed-forward coefficient: per moving axis the kf that minimises
// the model's tracking error over that axis's reference command (e is linear
// in kf, so a closed form), then the mean over the axes.
// An axis whose command spans less than this (mm or degrees) stands for ChooseFeedForward.
inline constexpr double kStandingAxisRange = 1e-6;
struct FeedForwardChoice {
  std::array<double, kAxisCount> per_axis{};  // NaN for an axis that does not move
  double averaged = 0;
};
FeedForwardChoice ChooseFeedForward(const TrackingErrorModel& model, const std::vector<AxisVector>& command, double dt_s);

// An axis whose identification residual exceeds this share of the identification
// run's tracking error (RMS, feed-forward on) is one the model does not describe
// well: the correction removes what the model predicts, so on such an axis it
// delivers markedly less (docs/fiveaxis.md, "Model fit").
inline constexpr double kPoorFitFraction = 0.06;

// Warnings, one per axis whose fit_rms exceeds kPoorFitFraction × signal_rms
// (empty when every axis is described well, or the model holds no fit figures).
std::vector<std::string> ModelFitWarnings(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names);

std::string ModelToJson(const TrackingErrorModel& model, const std::array<std::string, kAxisCount>& names);
// InputError naming the source and the field for a malformed model: a missing
// or non-numeric field, coefficients not 29 (or, written before the drive
// mode, 21) finite plausible numbers, a drive mode outside 0 … 1000 Hz or
// damping outside 0 … 1, a derivative window outside 0 … 1 s, axis names other than the machine's
// (machine_axes, in order — also catches a name given twice).
TrackingErrorModel ModelFromJson(const std::string& text, const std::string& source,
                                 const std::array<std::string, kAxisCount>& machine_axes);

}  // namespace trueaxis::fiveaxis
