#pragma once
// PitchErrorProfile: the geometric positioning error of one screw at 20 °C as
// a function of machine position (seed 002): progressive (linear + bow),
// periodic harmonics of the lead, and a smooth random part built from the
// machine's serial seed; plus the direction-dependent flank part.
#include <cstdint>
#include <vector>

#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {

class PitchErrorProfile {
 public:
  PitchErrorProfile(const AxisDescription& axis, std::uint64_t serial_seed);
  // Error (actual − commanded) of the screw alone at x, µm; `direction` +1/−1
  // adds ± half the flank difference.
  double ErrorUm(double x_mm, int direction) const;

 private:
  struct Wave { double k_rad_per_mm, amp_um, phase; };
  double travel_mm_ = 0, progressive_um_ = 0, curvature_um_ = 0;
  std::vector<Wave> periodic_, random_, flank_;
};

}  // namespace trueaxis::sim
