#pragma once
// The CNC interpolator (docs/fiveaxis.md, "Interpolator"): turns a tool path
// into joint commands, one per servo period. Each move runs at its feed (tool
// tip, mm/min), slowed where an axis would exceed its velocity limit; runs of
// moves without a corner sharper than corner_stop_deg share one jerk-limited
// speed profile (rectangular speed filtered by two moving averages: the
// acceleration time feed/accel and the jerk time accel/jerk), so the tip
// stays exactly on the programmed lines. Inverse-time (G93) moves take their
// programmed durations as they are. Between points of a move the tip moves on
// the straight line and the rotary axes linearly; joints come from the
// inverse kinematics.
#include <cstddef>
#include <vector>

#include "trueaxis/fiveaxis/tool_path.hpp"

namespace trueaxis::fiveaxis {

// The interpolator holds one joint vector per servo period and every run
// after it (drives, contour, correction) several more: about 1 kB per period
// in `fiveaxis correct`. A path needing more periods than this (500 s at
// 2000 Hz) is refused before anything is allocated — an InputError naming the
// program line (or the path's feed option) and what would fit.
inline constexpr std::size_t kMaxServoSamples = 1'000'000;

struct Trajectory {
  double dt_s = 0;
  std::vector<AxisVector> joints;  // commanded joints, one per servo period
};

// settle_s: the machine rests at the start and at the end for this long.
// Throws InputError when the path needs more than kMaxServoSamples periods.
Trajectory Interpolate(const ToolPath& path, const FiveAxisMachine& m, double settle_s = 0.05);

// Joints of every path vertex (inverse kinematics).
std::vector<AxisVector> VertexJoints(const ToolPath& path, const Kinematics& kin);

}  // namespace trueaxis::fiveaxis
