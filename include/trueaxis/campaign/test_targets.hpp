#pragma once
// The target positions of an axis's bidirectional laser test, as ISO 230-2 asks (docs/real-machine.md
// "Targets"): at least five targets per metre of measurement travel and at least five in all; target i
// at P_i = P_1 + (i − 1)·p + r_i, with p the even spacing over the measurement travel and r_i a
// different random value at each inner target, so the lead's periodic error is sampled at every phase
// rather than at one (|r_i| ≤ min(lead/2, p/4), which keeps the order and spacing); the first and last
// targets at the ends of the measurement travel, which leaves room for the overrun beyond each end
// inside the soft limits. The list is drawn once per campaign (a seed) and kept for every state:
// the fit compares the states at the same targets.
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/campaign/campaign_machine.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"

namespace trueaxis::campaign {

struct TargetOptions {
  // Defaults: the virtual machine's laser test (sim::LaserOptions): targets every ~25 mm, 5 runs,
  // 5 mm overrun, 3 s at each target, 2000 mm/min between targets.
  double spacing_mm = sim::LaserOptions{}.spacing_mm;
  double overrun_mm = sim::LaserOptions{}.overrun_mm;
  double end_clearance_mm = 1;   // kept between the overrun and each soft limit
  int runs = sim::LaserOptions{}.runs;
  double dwell_s = sim::LaserOptions{}.dwell_s;
  double feed_mm_min = sim::LaserOptions{}.feed_mm_min;
  std::uint64_t seed = 1;        // the random component r_i
  bool random_component = true;  // false: evenly spaced (the lead's error is then sampled at few phases)

  bool IsValid(std::string* why) const;
};

struct AxisTargets {
  std::string axis;
  std::vector<double> targets_mm;  // ascending, machine coordinates, on a 1 µm grid
  double spacing_mm = 0;           // p
  double random_max_mm = 0;        // the bound of |r_i|
  double overrun_mm = 0;
  double dwell_s = 0;
  double feed_mm_min = 0;
};

// The minimum number of targets ISO 230-2 asks for over `measurement_travel_mm`.
int Iso230_2MinimumTargets(double measurement_travel_mm);

// InputError("command line", 0, "--spacing-mm"/"--overrun-mm", …) when the axis is too short for
// the overrun and five targets.
AxisTargets PlanAxisTargets(const CampaignAxis& axis, const TargetOptions& options);

// What in `t` breaks ISO 230-2 or the machine's limits (empty: none): a target or an overrun
// outside the soft limits, targets not strictly ascending, fewer than Iso230_2MinimumTargets, a
// spacing off the even spacing by more than the random bound.
std::vector<std::string> TargetProblems(const CampaignAxis& axis, const AxisTargets& t);

// How long one bidirectional test of `runs` runs takes: the moves at the feed, the dwells.
double TestDurationS(const AxisTargets& t, int runs);

}  // namespace trueaxis::campaign
