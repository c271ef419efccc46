#pragma once
// The tracking-error model's inverse (docs/fiveaxis.md, "Correction"): per axis,
// the joint command whose predicted actual position is the programmed one.
// For the programmed direction of motion the model is a linear, time-invariant
// filter of the command plus a friction term fixed by that direction, so
//     c − E(c) = q + friction  ⇒  (1 − H_E) D = G
// with G the predicted tracking error of the programmed command q and H_E the
// frequency response of the model's linear terms at kf: one division per
// frequency (FFT, zero-padded at both ends: the command stands before and after
// its moves, so G and the correction vanish there). Where the drive rings (a
// lightly damped speed loop under a heavy load) the model's 1 − H_E nearly
// vanishes and the passes of a fixed-point correction converge slowly or not
// at all; the division does not care. It is regularised (|1 − H_E|² + λ²) so a
// model that predicts an error as large as the command at some frequency gives
// a bounded correction there.
#include <vector>

#include "trueaxis/fiveaxis/tracking_model.hpp"

namespace trueaxis::fiveaxis {

inline constexpr double kModelInverseRegularisation = 0.05;  // λ: the correction is at most 1/(2λ) × G per frequency

// The joint commands whose model-predicted actual positions are `command` (same length).
std::vector<AxisVector> InvertTrackingModel(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                            double dt_s, double kf, double regularisation = kModelInverseRegularisation);

}  // namespace trueaxis::fiveaxis
