#pragma once
// The options every command that reads a laser measurement takes for a laser software's own CSV
// export (docs/formats.md "Mapped CSV"): --columns and --column-map, defined once here so the
// commands cannot drift apart.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "trueaxis/measure/measurement_file.hpp"

namespace trueaxis::cli {

struct MeasurementInputOptions {
  std::string columns;     // --columns "target_mm=Target [mm],deviation_um=Error [µm],run=Run,direction=Dir"
  std::string column_map;  // --column-map FILE.toml

  // The reader's options; InputError for a bad mapping (naming --columns or the mapping file).
  measure::MeasurementReadOptions Resolve() const;
  bool Given() const { return !columns.empty() || !column_map.empty(); }
  // Reads one measurement with these options.
  measure::Measurement Read(const std::string& path) const;
};

// Adds --columns and --column-map to `cmd`.
void AddMeasurementInputOptions(CLI::App* cmd, MeasurementInputOptions& options);

}  // namespace trueaxis::cli
