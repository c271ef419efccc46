#pragma once
// CompensationTable: the controller-neutral form of one axis's compensation
// table, between the model/measurement (resample.hpp) and the controller
// files (linuxcnc_table.hpp, sinumerik_table.hpp, fanuc_table.hpp,
// heidenhain_table.hpp, csv_table.hpp). Every writer takes one and every
// reader gives one back, so a round trip is compared in one place.
//
// Sign convention (docs/sign-convention.md): forward_um / reverse_um are
// CORRECTIONS (= −error), in µm, to be ADDED to the commanded position.
// Writers convert to the controller's own sign and unit; readers convert back.
//
// Applying the table (AppliedCorrectionUm) means what the controllers do:
// linear interpolation between points, the end value held beyond the ends,
// plus, for a unidirectional table, ±backlash/2 by direction (LinuxCNC's
// BACKLASH semantics), plus the position-dependent thermal line when the
// thermal part is kept out of the table (SINUMERIK temperature compensation).
#include <limits>
#include <string>
#include <vector>

#include "trueaxis/core/direction.hpp"

namespace trueaxis::exporter {

// The sign a file's values are written in. kCorrection = −error (trueaxis'
// default), kError = actual − commanded (what the laser saw).
enum class ValueSign { kCorrection, kError };
inline double SignFactor(ValueSign s) { return s == ValueSign::kCorrection ? 1.0 : -1.0; }

struct CompensationTable {
  std::string axis;
  std::vector<double> position_mm;  // strictly ascending
  std::vector<double> forward_um;   // correction approaching in + direction
  std::vector<double> reverse_um;   // correction approaching in − direction
  // false: forward_um == reverse_um (the mean curve) and backlash_um applies.
  bool bidirectional = true;
  // Unidirectional tables only: forward applied = value + backlash/2, reverse
  // applied = value − backlash/2 (correction sign; > 0 for ordinary lost motion).
  double backlash_um = 0;
  // Reference point (Px of the model; the Fanuc reference position).
  double reference_position_mm = std::numeric_limits<double>::quiet_NaN();
  // Thermal line kept OUT of the table values (SINUMERIK temperature
  // compensation): ERROR = tan_beta·(thermal_reference_mm − x), as in the
  // model (docs/sign-convention.md). 0 when the thermal part is in the values.
  double thermal_tan_beta_um_per_mm = 0;
  double thermal_reference_mm = 0;
  // Free-text provenance lines (model, thermal state, options) for headers.
  std::vector<std::string> provenance;

  std::size_t size() const { return position_mm.size(); }
  // Equidistant spacing, or NaN when the positions are not equidistant (1e-9 mm).
  double UniformSpacingMm() const;
};

// The correction the controller applies at `position_mm` approached in `direction`.
double AppliedCorrectionUm(const CompensationTable& table, double position_mm, Direction direction);

// Structural checks every reader and writer relies on; throws
// InputError(source, line 0, field, why): empty table, column sizes differ,
// non-finite or implausible values (positions beyond ±100 m, corrections or
// backlash beyond ±10 000 µm: core/plausibility.hpp), positions not strictly
// ascending (field "position_mm[i]"). Writers call it first, so such a value
// is refused rather than written into a controller file.
void ValidateTable(const CompensationTable& table, const std::string& source);

// What every table reader (`export --read`) checks on top of ValidateTable, since a controller file may
// come from anywhere: at least 2 points (every writer needs 2), positions within ±100 000 mm and
// corrections and backlash within ±10 000 µm (core/plausibility.hpp) — a LinuxCNC file holding µm
// instead of mm, a FANUC point P99999 — naming the line of the point (`point_lines[i]`, 0 when unknown).
void ValidateReadTable(const CompensationTable& table, const std::string& source, const std::vector<int>& point_lines);

}  // namespace trueaxis::exporter
