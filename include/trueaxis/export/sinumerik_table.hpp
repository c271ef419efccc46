#pragma once
// SINUMERIK 840D leadscrew / measuring-system error compensation (LEC/EEC)
// table plus the temperature-compensation settings matching trueaxis's
// thermal model (docs/export.md, Siemens Function Manual K3).
//
//   %_N_AX_EEC_INI
//   CHANDATA(1)
//   $AA_ENC_COMP[0,0,X1]=0.003        ; value of point 0, mm
//   ...
//   $AA_ENC_COMP_STEP[0,X1]=1.0       ; distance between points, mm
//   $AA_ENC_COMP_MIN[0,X1]=-200.0     ; first point
//   $AA_ENC_COMP_MAX[0,X1]=600.0      ; last point
//   $AA_ENC_COMP_IS_MODULO[0,X1]=0
//   M17
//
// Sign: the LEC value modifies the actual value; "a positive compensation
// value causes the machine axis to move in the negative direction", i.e. the
// value is the ERROR (actual − commanded) in mm. One curve per encoder: the
// table is unidirectional; the backlash goes to MD32450 $MA_BACKLASH.
//
// Temperature compensation (SD43900/43910/43920, MD32750): Siemens writes
// K = TEMP_COMP_ABS_VALUE + TEMP_COMP_SLOPE·(P_actual − TEMP_COMP_REF_POSITION).
// trueaxis's thermal error is tanβ·(Px − x) with Px the reference point, so
// TEMP_COMP_REF_POSITION = Px, TEMP_COMP_SLOPE = −tanβ/1000 (µm/mm → mm/mm),
// TEMP_COMP_ABS_VALUE = 0. Machine and setting data are written as comments
// (the user sets them deliberately); the reader takes them back from there.
#include <string>
#include <string_view>

#include "trueaxis/export/compensation_table.hpp"

namespace trueaxis::exporter {

struct SinumerikOptions {
  std::string axis_name = "X1";  // machine axis name in $AA_ENC_COMP[..,..,AXn]
  int encoder = 0;               // measuring system: 0 or 1
  bool IsValid(std::string* why) const;
};

std::string WriteSinumerikEec(const CompensationTable& table, const SinumerikOptions& options,
                              const std::string& source);
// The machine/setting data a user must set, one per line (also in the file as comments).
std::string SinumerikMachineData(const CompensationTable& table, const SinumerikOptions& options);

CompensationTable ReadSinumerikEec(std::string_view text, const std::string& source);

// The LEC value the table applies at its reference point (forward, with the frozen thermal part and
// half the backlash, as the control applies it), µm; Siemens recommends 0 there so that nothing
// jumps when LEC activates after referencing. NaN when the reference lies outside the table.
double SinumerikValueAtReferenceUm(const CompensationTable& table);

}  // namespace trueaxis::exporter
