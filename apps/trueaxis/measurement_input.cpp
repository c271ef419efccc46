#include "measurement_input.hpp"

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {

measure::MeasurementReadOptions MeasurementInputOptions::Resolve() const {
  measure::MeasurementReadOptions out;
  if (!columns.empty() && !column_map.empty())
    throw InputError("command line", 0, "--columns", "give the mapping once: --columns or --column-map, not both");
  if (!columns.empty()) out.columns = measure::ParseColumnsOption(columns);
  if (!column_map.empty()) out.columns = measure::ReadColumnMapFile(column_map);
  return out;
}

measure::Measurement MeasurementInputOptions::Read(const std::string& path) const {
  return measure::ReadMeasurementFile(path, Resolve());
}

void AddMeasurementInputOptions(CLI::App* cmd, MeasurementInputOptions& o) {
  cmd->add_option("--columns", o.columns,
                  "a laser software's CSV export: its columns, e.g. \"target_mm=Target [mm],deviation_um=Error [µm],"
                  "run=Run,direction=Dir\" (keys: target_mm|target_in, deviation_um|_mm|_nm, run, direction, "
                  "deviation_um[<run><+|->], time_s, t_<sensor>_c, forward=<words>, reverse=<words>; docs/formats.md)");
  cmd->add_option("--column-map", o.column_map, "the same mapping as a TOML file (docs/formats.md)")
      ->check(CLI::ExistingFile);
}

}  // namespace trueaxis::cli
