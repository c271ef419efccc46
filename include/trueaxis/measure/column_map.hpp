#pragma once
// How a laser software's CSV export maps onto a measurement (docs/formats.md, "Mapped CSV"): which
// of its columns holds the target, the deviation, the run, the direction, the time and each
// temperature, in which unit, and which of its direction words mean + and −.
//
// Given on the command line as `--columns "target_mm=Target [mm],deviation_um=Error [µm],run=Run,
// direction=Dir"` or as a TOML file (`--column-map FILE.toml`, the same keys at the top level plus an
// optional [metadata] table). Both go through one key parser, so they take the same keys:
//   target_mm | target_in            the target column (inches converted ×25.4 because named so)
//   deviation_um | deviation_mm | deviation_nm   the deviation (actual − target) column
//   run, direction                   run number and direction columns (long layout)
//   deviation_um[<run><+|->]         one deviation column per run and direction (wide layout),
//                                    e.g. deviation_um[1+]=Run 1 up (also _mm / _nm)
//   time_s, t_<sensor>_c             time and temperature columns
//   forward, reverse                 direction words of the file, '|'-separated (forward=up|U)
// A key that is none of these, a key given twice or an empty column name is an InputError naming
// the mapping's source ("--columns" or the file, with its line) and the key.
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "trueaxis/core/direction.hpp"

namespace trueaxis::measure {

// One mapped column: its name in the file's header, the unit its key names and the factor to the
// canonical unit (µm for deviations, mm for targets).
struct MappedColumn {
  std::string key;     // the mapping key as written: "deviation_mm", "t_nut_c", "deviation_um[2-]"
  std::string column;  // the header name in the file
  std::string unit;    // "um", "mm", "nm", "in", "s", "c"
  double scale = 1;
};

struct RunColumn {
  int run = 1;
  Direction direction = Direction::kForward;
  MappedColumn deviation;
};

struct ColumnMap {
  std::string source;  // "--columns" or the mapping file, for errors
  std::optional<MappedColumn> target, deviation, run, direction, time;
  std::vector<std::pair<std::string, MappedColumn>> temperatures;  // sensor name → column
  std::vector<RunColumn> run_columns;                              // wide layout
  std::vector<std::pair<std::string, Direction>> direction_words;  // lower-case word → direction
  std::vector<std::pair<std::string, std::string>> metadata;       // a mapping file's [metadata]
  std::map<std::string, int> key_lines;                            // mapping-file line of each key

  int LineOf(const std::string& key) const;
  // Every mapped column, in key order, for the header check.
  std::vector<const MappedColumn*> Columns() const;
};

// Adds one `key=value` of a mapping to `map` (value: a column name, or for forward/reverse the
// direction words). InputError(map.source, line, key, why) on an unknown key, a key given twice, an
// empty value or a direction word given for both directions.
void SetColumnMapKey(ColumnMap& map, const std::string& key, const std::string& value, int line = 0);

// `--columns` text: comma-separated key=value pairs (a pair holding a comma in double quotes).
ColumnMap ParseColumnsOption(std::string_view text, const std::string& source = "--columns");
// A TOML mapping file.
ColumnMap ParseColumnMapToml(std::string_view text, const std::string& source);
ColumnMap ReadColumnMapFile(const std::string& path);

// The unit a column's name states in a trailing [..] or (..) ("Error [µm]" → "um", "Pos (in)" →
// "in", "Temp [°C]" → "c"); nullopt when the name states none that trueaxis knows.
std::optional<std::string> UnitTagOf(std::string_view column);

// A direction word of a mapped file: the mapping's own words first, then the recognised ones
// (+/-, up/down, fwd/rev, forward/backward/reverse, pos/neg, 1/-1); nullopt otherwise.
std::optional<Direction> MappedDirection(const ColumnMap& map, std::string_view word);

}  // namespace trueaxis::measure
