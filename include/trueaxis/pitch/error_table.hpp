#pragma once
// PitchErrorTable: the ball-screw pitch error of one axis sampled once per
// lead (seed 002 §2.3: "以每个螺距为位置点", one point per lead), per direction
// of approach, with linear interpolation between the samples.
//
// Sign (docs/sign-convention.md): the values are ERRORS (actual − commanded,
// µm), as the laser saw them; the correction the CNC adds is −error.
//
// Interpolation (docs/pitch-error-file.md):
//   - inside the table: linear between the two neighbouring samples of the
//     direction asked for;
//   - the table vouches for the range it was measured over (the laser run's
//     first…last target, `measured_from_mm`…`measured_to_mm`); beyond it the
//     value at its end is held (a controller holds its end values the same
//     way), never extrapolated, and the lookup says `outside` once the
//     position lies more than model::kMeasuredRangeToleranceMm beyond it, so a
//     caller can count it, report it apart and alarm. A table without the
//     range (a file that does not record it) vouches for its own ends;
//   - the direction is the direction of approach (+1 forward, −1 reverse);
//     which one applies across a reversal is the interpolator's decision
//     (sim/interpolator.hpp): the table itself holds both curves.
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/core/direction.hpp"
#include "trueaxis/export/resample.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::pitch {

struct PitchErrorTable {
  std::string axis;
  double lead_mm = 0;
  int samples_per_lead = 1;       // 1: once per lead (seed 002); more resolves the lead harmonics
  double reference_mm = 0;        // the grid passes through it (the homing reference)
  std::vector<double> position_mm;  // reference + k·lead/samples_per_lead, ascending
  std::vector<double> error_up_um;  // error approaching forward (+)
  std::vector<double> error_down_um;  // error approaching in reverse (−)
  std::vector<std::string> provenance;  // free text: what it was made from
  // The range it was measured over (first…last target): what it vouches for. Inside the table's
  // own span; its end samples may lie up to one spacing beyond it (the grid point past an end
  // target off the grid). NaN: unknown (the table's ends are taken; MeasuredRangeWarning).
  double measured_from_mm = std::numeric_limits<double>::quiet_NaN();
  double measured_to_mm = std::numeric_limits<double>::quiet_NaN();

  std::size_t size() const { return position_mm.size(); }
  double SpacingMm() const { return lead_mm / samples_per_lead; }
  bool HasMeasuredRange() const { return std::isfinite(measured_from_mm) && std::isfinite(measured_to_mm); }
  double VouchedFromMm() const { return HasMeasuredRange() ? measured_from_mm : position_mm.front(); }
  double VouchedToMm() const { return HasMeasuredRange() ? measured_to_mm : position_mm.back(); }
  // Outside the vouched range by more than model::kMeasuredRangeToleranceMm.
  bool OutsideVouchedRange(double x_mm) const;
};

// For a table whose range is unknown: one line saying so and which range is assumed; nullopt when
// the table records it. `source` names the file.
std::optional<std::string> MeasuredRangeWarning(const PitchErrorTable& table, const std::string& source);

// For a measurement that leaves part of the axis's travel 0…travel_mm unmeasured (beyond
// model::kMeasuredRangeToleranceMm at either end): one line naming the uncovered zones; nullopt
// when it covers the travel or the travel is unknown (NaN).
std::optional<std::string> UncoveredTravelWarning(double first_mm, double last_mm, double travel_mm,
                                                  const std::string& source);

struct TableLookup {
  double error_um = 0;
  bool outside = false;  // beyond the vouched range (more than the tolerance): the end value was held
};

TableLookup LookupError(const PitchErrorTable& table, double x_mm, Direction direction);
// −error, with `direction` +1 / −1 (what the interpolator asks for).
double CorrectionUm(const PitchErrorTable& table, double x_mm, int direction);

// Structural checks (InputError naming `source` and the field): at least 2
// points, columns of equal size, finite and plausible values, lead 0.5–200 mm,
// samples_per_lead 1–64, positions ascending on the grid reference + k·spacing
// (within 1 µm).
void ValidatePitchTable(const PitchErrorTable& table, const std::string& source);

struct TableFromMeasurementOptions {
  double lead_mm = 0;             // 0: the measurement's `lead_mm` metadata
  int samples_per_lead = 1;
  double reference_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: `reference_mm` metadata, else the first target
};

// From a laser run (a fine cycle, or a user's own file): the mean deviation per
// target and direction (ISO 230-2 x̄_i↑, x̄_i↓), sampled on the grid over the
// measured range — exactly at targets that lie on the grid, else linearly
// between the two neighbouring targets; an end target off the grid gets the
// grid point beyond it too, with its value (held), so the table spans the
// whole measured range, which it records (measured_from_mm…measured_to_mm). Refused (InputError) when the targets
// are further apart than the table's spacing: a once-per-lead table cannot be
// read off a coarse ISO run (the lead's harmonics alias).
PitchErrorTable TableFromMeasurement(const measure::Measurement& m, const TableFromMeasurementOptions& options);

// The table that fits the screw: the fewest samples per lead (1, 2, 3, …, as
// dense as the run's targets allow) whose table reproduces the run's mean
// deviations at every target within the tolerance — by default the run's own
// scatter, one σ (a quarter of the unidirectional repeatability R↑/R↓ = 4s),
// at least 0.5 µm (below that the table would fit the run's noise). A screw whose lead harmonics are strong needs more than
// once per lead (its periodic error falls between once-per-lead samples).
struct SamplesPerLeadChoice {
  int samples_per_lead = 1;
  double interpolation_error_um = 0;  // MaxInterpolationErrorUm of the chosen table
  double tolerance_um = 0;
  bool within_tolerance = true;       // false: the densest table the run allows, still over the tolerance
  std::string Describe() const;       // one line for the user
};
SamplesPerLeadChoice ChooseSamplesPerLead(const measure::Measurement& m, const TableFromMeasurementOptions& base,
                                          double tolerance_um = std::numeric_limits<double>::quiet_NaN());

// From a fitted model (docs/model-file.md): its geometric + thermal error at
// the frozen state of `freeze` (cold by default), on the grid through the
// model's reference point inside its valid range (its measured_range_mm when
// it records one); the table vouches for that span.
PitchErrorTable TableFromModel(const model::AxisModel& axis, double lead_mm, int samples_per_lead,
                               const exporter::ThermalFreeze& freeze, const std::string& source);

// To a controller table (exporter::CompensationTable, corrections) for the
// writers of export/: at the table's own points, or on the grid the options
// give (linear interpolation of this table). A table with more points than
// options.max_points is refused naming the spacing that would fit — never
// truncated. `source` names the error file in messages.
exporter::ResampleResult ResamplePitchTable(const PitchErrorTable& table, const exporter::ResampleOptions& options,
                                            const std::string& source);

// Largest |table − reference curve| at the given fine points (µm), per
// direction: the table's interpolation error against a finer measurement.
double MaxInterpolationErrorUm(const PitchErrorTable& table, const measure::Measurement& fine);

}  // namespace trueaxis::pitch
