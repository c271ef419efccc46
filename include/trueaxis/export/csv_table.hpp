#pragma once
// Plain CSV compensation table for any other controller (docs/export.md):
//
//   # trueaxis compensation table
//   # axis: X
//   # sign: correction            (or: error)
//   # mode: bidirectional         (or: unidirectional, with # backlash_um: b)
//   # reference_position_mm: 0
//   position_mm,forward_correction_um,reverse_correction_um
//
// Numbers are shortest round-trip text, so Read(Write(t)) == t exactly.
#include <string>
#include <string_view>

#include "trueaxis/export/compensation_table.hpp"

namespace trueaxis::exporter {

std::string WriteCsvTable(const CompensationTable& table, ValueSign sign, const std::string& source);
CompensationTable ReadCsvTable(std::string_view text, const std::string& source);

}  // namespace trueaxis::exporter
