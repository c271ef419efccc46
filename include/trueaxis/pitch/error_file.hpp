#pragma once
// The pitch error file (docs/pitch-error-file.md): one PitchErrorTable as
// text — "# key: value" metadata, the header
// `position_mm,error_up_um,error_down_um` and one row per sample, once per
// lead (or samples_per_lead per lead), values as ERRORS in µm.
//
// The reader is strict and names file, line and field on every error
// (InputError): missing axis / lead_mm, an unknown format version, a wrong
// header, a row without three numbers, implausible values, positions that
// are not ascending on the lead grid, fewer than two rows.
#include <string>
#include <string_view>

#include "trueaxis/pitch/error_table.hpp"

namespace trueaxis::pitch {

inline constexpr const char* kPitchErrorFormat = "trueaxis-pitch-error-v1";

std::string FormatPitchErrorFile(const PitchErrorTable& table);
void WritePitchErrorFile(const PitchErrorTable& table, const std::string& path);

PitchErrorTable ParsePitchErrorFile(std::string_view text, const std::string& source);
PitchErrorTable ReadPitchErrorFile(const std::string& path);

}  // namespace trueaxis::pitch
