#pragma once
// The seed-002 proof on the virtual machine (docs/pitch-error-file.md, "Proof"):
// fine calibration on day 0 (laser zeroed at the reference after homing),
// the once-per-lead table from it, then (right after, or on day `verify_day`)
// the axis is re-homed and measured again at lead/per_lead spacing with the table applied
// ahead of the motion by the interpolator. Figures before and after, as seed
// 002 gives them (maximum positioning error, uncertainty = 3σ) and by
// ISO 230-2:2014 (A, E, R, B), plus what is left and why: the table's
// interpolation error (between its samples: the lead's periodic error a
// once-per-lead table cannot see) against the repeatability (3σ).
// Also the following error of the correction vs feed, ahead and late.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/analysis/evaluation.hpp"
#include "trueaxis/pitch/fine_cycle.hpp"

namespace trueaxis::pitch {

struct PositioningFigures {
  int targets = 0;
  double max_error_um = 0;    // largest |deviation| of any reading (seed 002: 最大定位误差)
  double uncertainty_um = 0;  // seed 002's 3σ error band: 3 × the standard deviation of all readings
                              //   (systematic curve and scatter together; what a table can shrink)
  double repeatability_3s_um = 0;  // 3σ, σ pooled run-to-run: what no table can remove
  analysis::AxisResult iso;   // ISO 230-2:2014
};

PositioningFigures Figures(const measure::Measurement& m);
// The readings of `m` at targets on the grid reference + k·spacing (1 µm).
measure::Measurement AtGrid(const measure::Measurement& m, double reference_mm, double spacing_mm);

// The readings of `m` at targets inside (or outside) the table's vouched range
// (PitchErrorTable::OutsideVouchedRange: beyond it by more than the tolerance).
measure::Measurement InVouchedRange(const measure::Measurement& m, const PitchErrorTable& table, bool inside = true);

// Before/after figures of one table: at every fine target inside the range the
// table vouches for and at the lead points only (as seed 002 measured), and
// what is left and why. Targets beyond that range (where the table's end
// values were held) are reported apart, never mixed into the figures.
struct PitchComparison {
  PositioningFigures before, after;                  // at every fine target in the vouched range
  PositioningFigures before_at_lead, after_at_lead;  // at the lead points only
  double interpolation_error_um = 0;  // max |before mean − table|, per direction (what the table cannot see)
  double drift_um = 0;  // max |after bidirectional mean| at the lead points, where the table was exact:
                        // what moved between calibration and use (thermal growth, reference after re-homing)
  double vouched_from_mm = 0, vouched_to_mm = 0;  // the table's measured range
  int outside_targets = 0;               // targets of `after` beyond it
  double outside_before_max_um = 0, outside_after_max_um = 0;  // largest |deviation| there, before → after
  // The largest share of the residual: "interpolation" (interpolation_error_um), "repeatability"
  // (after.repeatability_3s_um) or "drift" (drift_um).
  std::string Dominant() const;
};

PitchComparison ComparePitch(const measure::Measurement& before, const measure::Measurement& after,
                             const PitchErrorTable& table);

struct FollowingPoint {
  double feed_mm_min = 0;
  sim::MoveStats ahead, late;
};

// The simulated motion of one feed's move is bounded (the work is ∝ its
// duration: 300 mm at 1 mm/min took 23 s of CPU, 0.001 mm/min about 6 h).
inline constexpr double kMaxFollowingMoveS = 3600;

// Following error of the correction (interpolator statistics) for one long
// forward move across the table (at most 300 mm) at each feed, ahead and late.
// Every feed is checked first: InputError(field "--feeds") for a feed that is
// not finite, not positive, beyond 1e6 mm/min, or whose move would last more
// than kMaxFollowingMoveS (the message gives the lowest feed that fits).
std::vector<FollowingPoint> FollowingErrorVsFeed(const sim::MachineDescription& machine, std::size_t axis,
                                                 const PitchErrorTable& table, const std::vector<double>& feeds_mm_min,
                                                 const sim::InterpolatorOptions& interpolator, std::uint64_t seed);

struct PitchProofOptions {
  std::uint64_t seed = 1;
  FineCycleOptions cycle;            // per_lead 4: measured at lead/4
  int samples_per_lead = 1;          // the table: once per lead; 0: ChooseSamplesPerLead from the calibration run
  int verify_day = 0;                // 0: re-homed and verified right after the calibration (the floor);
                                     // N: N days later, 07:00 (adds the drift of another day)
  sim::HomingMethod homing = sim::HomingMethod::kSwitchAndIndex;
  sim::InterpolatorOptions interpolator;  // 2 ms, ahead
  std::vector<double> feeds_mm_min = {1000, 5000, 10000, 20000, 40000};
};

struct PitchProofResult {
  std::string machine, axis;
  double lead_mm = 0, travel_mm = 0;
  PitchErrorTable table;
  std::optional<SamplesPerLeadChoice> samples_choice;  // when chosen from the run (samples_per_lead 0)
  measure::Measurement before_run, after_run;
  PitchComparison c;
  double homing_shift_um = 0;         // reference error after re-homing − on the calibration day (truth)
  std::size_t outside_table_lookups = 0;
  std::vector<FollowingPoint> following;
  std::string Report() const;  // a few lines of text
};

PitchProofResult RunPitchProof(const sim::MachineDescription& machine, std::size_t axis, const PitchProofOptions& options);

}  // namespace trueaxis::pitch
