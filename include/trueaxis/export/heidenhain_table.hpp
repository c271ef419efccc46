#pragma once
// HEIDENHAIN nonlinear axis-error compensation: a compensation-value table
// (*.COM) per state and an assignment table (*.CMA) with one line per state,
// of which exactly one is ACTIVE (docs/export.md; MANUALplus 620 / TNC
// technical manuals).
//
//   BEGIN X_COLD.COM MM
//   NR    AXISPOS       X             BACKLASH
//   0     +0.0000       +0.0012       -0.0030
//   [END]
//
// AXISPOS: compensation point w.r.t. the machine datum, mm. Axis column: the
// compensation value, mm (sign: --sign, default correction; see
// docs/export.md for what could not be verified). BACKLASH: the additional
// value for the negative direction of traverse (reverse − forward), mm.
//
//   BEGIN X.CMA
//   NR    X                 ACTIVE  DOC
//   0     X_COLD.COM        *       cold, coolant off
//   1     X_FLOOD.COM               coolant flood, nut=30 bearing=28
//   [END]
//
// Columns are located by the header's column starts, as the control does.
#include <string>
#include <string_view>
#include <vector>

#include "trueaxis/export/compensation_table.hpp"

namespace trueaxis::exporter {

inline constexpr int kHeidenhainMaxPoints = 256;

std::string WriteHeidenhainCom(const CompensationTable& table, const std::string& file_name, ValueSign sign,
                               const std::string& source);
CompensationTable ReadHeidenhainCom(std::string_view text, ValueSign sign, const std::string& source);

struct CmaLine {
  std::string com_file;     // e.g. X_COLD.COM
  bool active = false;
  std::string description;  // DOC column
};

// Exactly one active line; file names must end in .COM.
std::string WriteHeidenhainCma(const std::string& axis, const std::string& file_name, const std::vector<CmaLine>& lines,
                               const std::string& source);
std::vector<CmaLine> ReadHeidenhainCma(std::string_view text, const std::string& axis, const std::string& source);

}  // namespace trueaxis::exporter
