#pragma once
// LinuxCNC screw compensation file for [JOINT_n] COMP_FILE (docs/export.md).
//
//   COMP_FILE_TYPE 0: "nominal forward-actual reverse-actual" per line, mm
//   COMP_FILE_TYPE 1: "nominal forward-trim reverse-trim" per line, mm
//
// LinuxCNC (src/emc/motion/usrmotintf.cc, usrmotLoadComp) converts type 0 to
// trims as trim = nominal − actual and adds the trim to the command, so a
// trim is a CORRECTION and actual = nominal + error. Its loader stops at the
// first line that is not three numbers, so the file carries no comments; it
// keeps at most 256 triplets per joint; positions must ascend.
// With COMP_FILE set LinuxCNC ignores [JOINT_n]BACKLASH (ini-config), so a
// unidirectional table's backlash is folded into the columns (±backlash/2,
// LinuxCNC's own backlash rule) and the INI lines say so.
#include <string>
#include <string_view>

#include "trueaxis/export/compensation_table.hpp"

namespace trueaxis::exporter {

inline constexpr int kLinuxCncMaxPoints = 256;

struct LinuxCncOptions {
  int comp_file_type = 1;  // 0 or 1
  int joint = 0;           // [JOINT_n] of the INI snippet
  std::string comp_file_name = "comp.txt";
  bool IsValid(std::string* why) const;
};

std::string WriteLinuxCncCompFile(const CompensationTable& table, const LinuxCncOptions& options,
                                  const std::string& source);
// The [JOINT_n] lines to paste into the INI file.
std::string LinuxCncIniSnippet(const CompensationTable& table, const LinuxCncOptions& options);

// Strict reader: every non-blank line must be a triplet (LinuxCNC itself would
// silently stop reading there), positions strictly ascending, ≤ 256 lines.
CompensationTable ReadLinuxCncCompFile(std::string_view text, int comp_file_type, const std::string& source);

}  // namespace trueaxis::exporter
