#pragma once
// User programs (docs/fiveaxis.md, "Programs"):
//  * a G-code subset: G0 G1, X Y Z and the machine's rotary letters (A C or
//    B C), F, G90/G91, G20/G21, G93/G94 (inverse-time feed, used by the
//    corrected program), N words, comments in () or after ';', '%' lines and
//    M2/M30. Coordinates are the tool tip in the workpiece frame (TCP mode).
//  * a CSV of tool tip and orientation: header x_mm,y_mm,z_mm then either
//    i,j,k (tool axis) or the rotary angles (a_deg|b_deg, c_deg), optional
//    feed_mm_per_min (else --feed) or duration_s (inverse time).
// Anything else — an unknown word, a G1 without a feed, a rotary value
// outside the machine's range, a bad number — is an InputError naming the
// file, line and word.
#include <string>

#include "trueaxis/fiveaxis/tool_path.hpp"

namespace trueaxis::fiveaxis {

ToolPath ParseGcodeProgram(const std::string& text, const std::string& source, const FiveAxisMachine& m);
// default_feed_mm_per_min: used when the CSV has no feed column (0 = required).
ToolPath ParseCsvProgram(const std::string& text, const std::string& source, const FiveAxisMachine& m,
                         double default_feed_mm_per_min);
// By extension: .csv → CSV, anything else G-code.
ToolPath ReadProgramFile(const std::string& path, const FiveAxisMachine& m, double default_feed_mm_per_min);

// Writes a path in the G-code subset (absolute, mm; inverse-time blocks as
// G93 with F = 1/min) or as CSV (x_mm..c_deg, duration_s or feed).
std::string WriteGcodeProgram(const ToolPath& path, const FiveAxisMachine& m, const std::string& header_comment);
std::string WriteCsvProgram(const ToolPath& path, const FiveAxisMachine& m);

}  // namespace trueaxis::fiveaxis
