#pragma once
// InstallationConfig: what one machine's installation (station::Installation) is built from —
// the loop's periods, the compensator's options and axes, the temperature pipeline ([signal]) and
// the model ([model]). The same for every way a machine is run: `trueaxis run`'s file
// (station::SiteConfig adds where the machine is, its history and its web page), a shop file's
// [[machine]] (server::ShopConfig), the demo and the HAL programs. Relative paths are resolved
// against the config file's folder; errors found after reading name the file, line and key.
#include <map>
#include <string>
#include <vector>

#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/compensator_options.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"

namespace trueaxis::station {

struct InstallationConfig {
  std::string source;           // the config file path
  std::string model_file;
  bool model_reload = true;     // watch the model file and swap a changed model in without stopping
  // Non-empty: the model file is a data-driven thermal model (trueaxis thermal fit: mlr, ridge,
  // pso-bp, hysteresis), deployed on these axes: CNC axis → the model's error channel.
  std::map<std::string, std::string> thermal_channels;
  double period_s = 0.010;
  double temperature_period_s = 0.1;  // the temperature worker's interval (temperatures change over seconds)
  double duration_s = 0;        // 0: until SIGINT/SIGTERM
  runtime::CompensatorOptions compensator;
  std::vector<runtime::AxisInterface> axes;
  // Seed 000's de-noising filter in the temperature judge in front of the compensator
  // (signal::MonitoredTemperatureSource); on by default. Off, the judge still applies its fault
  // rules (compensator.sensor.judge) to the unfiltered values: nothing reaches the step unjudged.
  bool signal_processing = true;
  std::string calibration_file;  // signal::CalibrationSet JSON (trueaxis calibrate), "" = none
  // Redundant probes ([signal] groups, e.g. two on one nut): checked against each other by the
  // pipeline (signal `disagreement`: farther apart than compensator.sensor.judge.max_disagreement_c,
  // a pair is lost together).
  std::vector<std::vector<std::string>> redundant_groups;
  int redundant_groups_line = 0;  // where [signal] groups was given (for errors naming a channel)
  // Where keys were given ("model.file", "machine.file", "axis[1].name", "web.listen", …), for the
  // errors found after reading (a missing file, a model of another machine, an axis the machine lacks).
  std::map<std::string, int> lines;
  int LineOf(const std::string& key) const {
    const auto it = lines.find(key);
    return it == lines.end() ? 0 : it->second;
  }
  // A file named by `key` ("model.file", "machine.file") must exist and not be a folder, else
  // InputError(source, its line, key, …) — the path alone did not say which setting named it.
  void RequireFile(const std::string& key, const std::string& path) const;
};

// The one temperature judge's options of an installation, built here only: the fault limits of
// its one policy ([sensor_fault], [signal] max_disagreement_c: compensator.sensor.judge), the
// redundant groups as neighbour groups, the filter off with [signal] enabled = false (judged all
// the same). The step judges no value.
signal::MonitorOptions TemperatureJudgeOptions(const InstallationConfig& config);

// Relative `path` against `base_dir` (the config file's folder); absolute and "" as given.
std::string ResolveConfigPath(const std::string& base_dir, const std::string& path);

// [signal] (the temperature pipeline: enabled, calibration, groups, max_disagreement_c) and
// [model] thermal_channels, read through `r` into `c` — shared by `run` and the shop file's
// machines (docs/server.md). `base`: the folder relative paths are resolved against.
void ReadSignalTable(TomlTableReader& r, const std::string& base, InstallationConfig& c);
void ReadThermalChannels(TomlTableReader& r, InstallationConfig& c);

// The installation's tables of a `run` file's root table `r` — [model] (required unless
// `model_required` is false: what `campaign log` opens before there is a model), [loop], the
// compensator's tables (runtime::ReadCompensatorTables) and [signal] — into `c` (its source set).
// Unknown keys of `r` are left for the caller's RejectUnknown (the file has other tables too).
void ReadInstallationTables(TomlTableReader& r, InstallationConfig& c, bool model_required);

}  // namespace trueaxis::station
