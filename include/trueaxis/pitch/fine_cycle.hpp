#pragma once
// Fine calibration of a ball-screw axis (seed 002 §1.3, §2.4): a bidirectional
// laser cycle over the full travel (its ends included, FineTargets) with targets on the lead grid — every lead
// and finer (lead/per_lead, default lead/4, so the first harmonic of the lead
// is resolved without aliasing) — moved by the virtual CNC's interpolator
// (sim/interpolator.hpp), with or without a pitch table applied.
//
// A fine session is what an engineer does on the virtual machine: the machine
// is homed (sim/homing.hpp), the laser set up and zeroed at the reference on
// day 0 (its tripod then stays), and on day `day` the axis is re-homed and
// measured — so a session on a later day sees exactly what re-homing did to
// a table made on day 0; on day 0 with a table, the calibration cycle is
// replayed first and the axis re-homed, so the verification differs from the
// calibration only by the table and the homing (the physical floor).
// Same machine file, seed and options: the same file.
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/pitch/error_table.hpp"
#include "trueaxis/sim/homing.hpp"
#include "trueaxis/sim/interpolator.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::pitch {

struct FineCycleOptions {
  int per_lead = 4;            // targets every lead/per_lead
  int runs = 3;                // bidirectional runs (2–20)
  double feed_mm_min = 2000;   // between targets
  double dwell_s = 1;          // settle + averaging at each target
  double overrun_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: min(5 mm, one lead); cut at the travel's ends
  // The shortest reversal: the end targets lie this far inside the travel's ends, so each is still
  // approached from its own side after reversing at the end (the lost motion is taken up within a
  // few µm). At most model::kMeasuredRangeToleranceMm: the table then vouches for the whole travel.
  double end_margin_mm = 0.25;

  bool IsValid(std::string* why) const;
};

// Covers the whole travel: reference + k·lead/per_lead inside [end_margin, travel − end_margin],
// and the two end targets end_margin and travel − end_margin themselves (when off that grid).
// The reversals overrun by `overrun_mm` where the travel allows, else reverse at its end.
std::vector<double> FineTargets(const sim::AxisDescription& axis, const FineCycleOptions& options);

// One bidirectional fine cycle on an axis whose laser is set up: the moves go
// through `ipo` (its feed-forward mode and table), readings from `laser`.
measure::Measurement RunFineCycle(sim::VirtualMachine& vm, std::size_t axis, sim::LaserInterferometer& laser,
                                  sim::CncInterpolator& ipo, const FineCycleOptions& options,
                                  const std::vector<std::pair<std::string, std::string>>& extra_metadata = {});

struct FineSessionOptions {
  std::uint64_t seed = 1;
  int day = 0;                 // 0: calibration day; > 0: re-homed and measured that many days later, 07:00.
                               // 0 with a table: the same day, right after the calibration cycle (replayed), re-homed
  sim::HomingMethod homing = sim::HomingMethod::kSwitchAndIndex;
  FineCycleOptions cycle;
  sim::InterpolatorOptions interpolator;   // mode kOff without a table
  const PitchErrorTable* table = nullptr;  // applied by the interpolator when given
};

struct FineSessionResult {
  measure::Measurement measurement;
  sim::HomingResult calibration_homing;  // day 0 (the laser's zero)
  sim::HomingResult homing;              // the homing before the measurement
  std::size_t outside_table_lookups = 0; // positions beyond the table's ends (end value held)
};

FineSessionResult RunFineSession(const sim::MachineDescription& machine, std::size_t axis, const FineSessionOptions& options);

}  // namespace trueaxis::pitch
