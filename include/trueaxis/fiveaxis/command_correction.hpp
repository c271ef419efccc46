#pragma once
// Seed 004's command correction (docs/fiveaxis.md, "Correction"): the model
// predicts each axis's residual tracking error under feed-forward; the
// predicted actual joints give, by forward kinematics, the predicted actual
// tool tip and axis; their difference from the commanded tip and rotary
// angles moves a virtual target the other way, whose inverse kinematics is
// the corrected axis command (= command + axis compensation). The first pass
// is seed 004's correction; further passes predict the error of the corrected
// command itself, their updates low-passed without phase (time constant
// update_filter_s) and shortened, per 30 ms window, to the fraction that
// leaves the least predicted residual; they converge towards the command
// whose predicted motion is the programmed one, but may stall at sharp friction
// transients (docs/fiveaxis.md, "Correction"). The end points are constraints:
// the correction fades in over the rest before the first move and out over the
// final rest, so the corrected command starts and ends exactly where the
// programmed one does.
#include <vector>

#include "trueaxis/fiveaxis/tool_path.hpp"
#include "trueaxis/fiveaxis/tracking_model.hpp"

namespace trueaxis::fiveaxis {

// How the corrected command is found (docs/fiveaxis.md, "Correction").
enum class CorrectionMethod {
  kModelInverse,  // the command whose predicted motion is the programmed one, solved per axis (default)
  kPasses,        // seed 004's correction through the kinematics, repeated `iterations` times
};

// The model inverted per axis: with the friction's direction of motion held at
// the programmed one the model is a linear filter of the command, so the
// command whose predicted actual motion is the programmed one follows by
// deconvolution (frequency domain, Tikhonov-regularised: the correction's gain
// is at most 1 / (2·regularization) at any frequency). Every axis's predicted
// actual position then equals its programmed one, so the tip and the tool axis
// do too (forward kinematics). The correction fades in and out over the rests
// at the ends, like CorrectCommands's.
inline constexpr double kInverseRegularization = 0.05;
std::vector<AxisVector> InvertTrackingModel(const TrackingErrorModel& model, const std::vector<AxisVector>& command,
                                            double dt_s, double kf, double regularization = kInverseRegularization);

std::vector<AxisVector> CorrectCommands(const Kinematics& kin, const TrackingErrorModel& model,
                                        const std::vector<AxisVector>& command, double dt_s, double kf, int iterations = 16,
                                        double update_filter_s = 0.005);

// Lengthens the rest after the last move until the model's predicted tracking
// error under kf has decayed below settle_tolerance (mm or deg, every axis),
// by at most max_extra_s: the correction of a path decays with it, so it can
// fade out before the end. Returns the rest added (s).
double ExtendRestUntilSettled(std::vector<AxisVector>& joints, const TrackingErrorModel& model, double dt_s, double kf,
                              double settle_tolerance = 1e-7, double max_extra_s = 2.0);

// The joint commands as a program (tool tip + rotary angles by forward
// kinematics), one inverse-time block per `samples_per_block` servo periods.
ToolPath CommandsToProgram(const std::vector<AxisVector>& joints, const Kinematics& kin, double dt_s,
                           int samples_per_block, const std::string& name);

}  // namespace trueaxis::fiveaxis
