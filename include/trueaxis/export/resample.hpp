#pragma once
// Resampling a fitted model (or a measurement) onto the equidistant grid a
// controller table needs (issue 6, MISSION M4/M9).
//
// Grid: start/spacing/count, each given or derived. Derived spacing is the
// smallest 1-2-5 step whose grid fits `max_points` over the axis range; a
// derived grid sits on round positions (multiples of the spacing, else of 1,
// 0.1, 0.01 mm, keeping every point the range allows; else the range's end to
// 0.001 mm), or on the reference point when one is given (or the format counts
// from it), and stays inside the range the model is valid for (no
// extrapolation; a 0.001 mm rounding may reach 0.0005 mm past it). A grid the
// options make impossible is an InputError naming the option; nothing is
// silently clipped.
//
// Values: correction = −Predict().total_um (docs/sign-convention.md) with the
// thermal part frozen at the given temperatures and coolant state, or kept
// out of the table as a line tanβ·(Px − x) for controllers that model it
// themselves (SINUMERIK temperature compensation).
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/export/compensation_table.hpp"
#include "trueaxis/measure/measurement.hpp"
#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::exporter {

struct ThermalFreeze {
  // Sensor name → temperature, °C. Key sensors of the axis and/or its ambient
  // sensor. Empty: the cold state (thermal part 0).
  std::vector<std::pair<std::string, double>> temperatures_c;
  CoolantState coolant = CoolantState::kOff;
};

struct ResampleOptions {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double start_mm = kNaN;    // NaN: derived
  double spacing_mm = kNaN;  // NaN: derived (1-2-5 step)
  int count = 0;             // 0: derived
  double range_min_mm = kNaN;  // axis range to cover; NaN: where the model/measurement is valid
  double range_max_mm = kNaN;
  int max_points = 256;        // the format's limit (checked, never clipped)
  bool bidirectional = true;   // false: mean curve + one backlash value
  bool zero_at_reference = false;
  double reference_position_mm = kNaN;  // NaN: the model's Px (first target for a measurement)
  // A derived grid is aligned on the reference point when it is given above or this is true (a
  // format that counts its points from the reference, FANUC); otherwise on round positions.
  bool reference_on_grid = false;
  ThermalFreeze thermal;
  bool thermal_in_table = true;  // false: table = geometric part, thermal line in table.thermal_*

  bool IsValid(std::string* why) const;
};

struct ResampleResult {
  CompensationTable table;
  double valid_min_mm = 0, valid_max_mm = 0;  // where the source is valid
  double zero_shift_um = 0;                   // subtracted from every value (zero at reference)
  double tan_beta_forward_um_per_mm = 0;      // total thermal slope at the frozen state (tanβ + ρΔT)
  double tan_beta_reverse_um_per_mm = 0;
  std::string BriefReport() const;
};

// `source` names the model file in error messages.
ResampleResult ResampleModel(const model::AxisModel& axis, const ResampleOptions& options, const std::string& source);

// Per-target mean deviation per direction (mean over runs) → correction.
// Without start/spacing/count the measured targets are the table points;
// otherwise the means are interpolated linearly onto the grid.
ResampleResult ResampleMeasurement(const measure::Measurement& m, const ResampleOptions& options);

// The shared tail of every resampler (also used by pitch/ for its error files):
// the unidirectional reduction (mean curve + backlash) and the zero at the
// reference point, as the options ask; then ValidateTable.
void FinishResample(ResampleResult& result, const ResampleOptions& options, const std::string& source);

// The provenance line (a comment in every format that writes one) naming the range the source was
// measured over and vouches for: "measured range (vouched for): 0.25…849.75 mm; beyond it the end
// values are held". A format without comments has no place for it.
std::string MeasuredRangeNote(double first_mm, double last_mm);

// The grid alone (exposed for tests and for formats that constrain it).
std::vector<double> MakeGrid(const ResampleOptions& options, double valid_min_mm, double valid_max_mm,
                             double reference_mm, const std::string& source);

}  // namespace trueaxis::exporter
