#pragma once
// The virtual drive of one axis (docs/fiveaxis.md, "Virtual machine"): at the
// servo rate a position P loop with optional velocity feed-forward
// (coefficient kf, seed 004) and acceleration feed-forward, a velocity PI
// loop, a current loop (first-order lag, saturating at the current limit),
// and the mechanics: motor + screw/gear + load inertia, viscous and Coulomb
// friction, integrated with sub-steps. Pure: no clock, no I/O.
#include <cstdint>
#include <vector>

#include "trueaxis/fiveaxis/machine.hpp"

namespace trueaxis::fiveaxis {

struct FeedForward {
  double velocity = 0;      // kf: 0 = none, 1 = full velocity feed-forward
  double acceleration = 0;  // 0..1 of the inertia-based torque feed-forward
};

class ServoDrive {
 public:
  ServoDrive(const DriveParams& p, double servo_rate_hz, FeedForward ff, double start_position);
  // One servo period with position command r (mm or deg); returns the
  // position measured at the start of the period (the sample that goes with r).
  double Step(double r);
  double position() const { return position_unit_; }
  std::int64_t saturated_periods() const { return saturated_; }

 private:
  DriveParams p_;
  double dt_s_;
  FeedForward ff_;
  double n_unit_, j_, b_, fc_;
  double position_unit_, omega_ = 0, integral_ = 0, current_ = 0;
  double r_prev_, v_ref_prev_ = 0;
  bool first_ = true;
  std::int64_t saturated_ = 0;
};

// Runs one drive over a whole command sequence (one sample per servo period);
// the measured positions, same length. `saturated` (optional) gets the count
// of periods at the current limit.
std::vector<double> RunDrive(const DriveParams& p, double servo_rate_hz, FeedForward ff,
                             const std::vector<double>& command, std::int64_t* saturated = nullptr);

}  // namespace trueaxis::fiveaxis
