#pragma once
// CncInterpolator: the position interpolator of the virtual CNC for one axis,
// with a compensation applied in it the way seed 002 §2.3 (Fig. 8, 9) does.
//
// Every interpolation cycle T (1–4 ms on a real CNC) the interpolator produces
// the next set point x_{k+1} = x_k ± v·T; the drive's fine interpolator moves
// the motor linearly between set points (`fine_steps` sub-steps per cycle, as a
// drive's position loop does). The correction c(x, direction) (µm, correction
// sign = −error, docs/sign-convention.md) enters the set point:
//
//   kAhead (feed-forward, seed 002):  x'_{k+1} = x_{k+1} + c(x_{k+1}, direction of [x_k, x_{k+1}])
//       — the correction for the interval about to be travelled, carried down
//       to the drive's fine interpolation: every fine sub-step's set point gets
//       the correction of the position it is about to reach, so between them
//       only the chord error of the correction over one sub-step remains. (Per
//       interpolation cycle alone, as the seed draws it, a 2 ms cycle at
//       40 m/min spans 1.3 mm — more than a quarter lead of a 5 mm screw — and
//       the chord between cycle set points cuts a fine table's corners.)
//   kLate (naive feedback): x'_{k+1} = x_{k+1} + c(x_k, direction of the previous interval)
//       — the correction of the position already reached: one interval late,
//       an error of about slope·v·T while moving, and the reversal is switched
//       one interval after the motion reversed.
//   kOff: no correction (the set point is the commanded position).
//
// Across a reversal the per-direction correction changes (by about the
// reversal value B); kAhead ramps it over the first interval of the new
// direction, while the drive takes up its play. At standstill the correction
// of the last direction of motion stays applied (a controller never switches
// tables without motion). The correction is written through CncLink, so the
// physics of the VirtualMachine (play, pitch, thermal growth) apply.
//
// Statistics per move: the "following error of the correction" is the applied
// correction minus the one exact for the position and direction at that
// instant (what a perfect, instantaneous compensation would apply), at each
// fine sub-step's end and middle (the drive moves linearly between sub-step
// set points: the middle shows the chord); the positioning error is
// actual − commanded, the truth.
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

enum class FeedForward { kOff, kAhead, kLate };
std::optional<FeedForward> ParseFeedForward(std::string_view text);  // "off", "ahead", "late"
std::string_view FeedForwardName(FeedForward f);

// Correction (µm, −error) at position x_mm approached in direction +1 / −1.
using AxisCorrectionFn = std::function<double(double x_mm, int direction)>;

struct InterpolatorOptions {
  double cycle_s = 0.002;  // interpolation cycle (seed 002's control card; 1–4 ms on CNCs)
  int fine_steps = 4;      // drive sub-steps per cycle
  FeedForward mode = FeedForward::kAhead;

  bool IsValid(std::string* why) const;
};

struct MoveStats {
  std::size_t cycles = 0;
  std::size_t samples = 0;
  double max_abs_following_um = 0;   // |applied − exact correction|, all samples
  double rms_following_um = 0;
  double max_abs_position_error_um = 0;  // |actual − commanded| while moving
  double sum_sq_following = 0;           // accumulators (Merge)
  void Merge(const MoveStats& o);
};

class CncInterpolator {
 public:
  // `correction` may be empty when mode is kOff.
  CncInterpolator(VirtualMachine& vm, std::size_t axis, InterpolatorOptions options, AxisCorrectionFn correction);
  const InterpolatorOptions& options() const { return o_; }

  // Interpolates a straight move to target_mm at feed (takes machine time).
  MoveStats MoveTo(double target_mm, double feed_mm_min);
  // Stands still for dwell_s; cycles keep running (kLate catches up here).
  void Dwell(double dwell_s);
  // Direction the correction is currently taken for (+1 / −1).
  int direction() const { return dir_; }

 private:
  double Correction(double x_mm, int dir) const;
  void Write(double correction_um);
  void Cycle(double x_from, double x_to, double c_to, double dt_s, int dir, bool reversing, MoveStats* stats);

  VirtualMachine& vm_;
  std::size_t axis_;
  InterpolatorOptions o_;
  AxisCorrectionFn correction_;
  int dir_ = 1;
  double applied_um_ = 0;
  std::vector<double> all_corrections_;
};

}  // namespace trueaxis::sim
