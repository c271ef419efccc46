#pragma once
// RunConfig: the TOML file of `trueaxis run --config FILE` (docs/runtime.md).
// Relative paths in it are resolved against the config file's folder.
// Every error is an InputError naming the file, line and key; unknown keys
// are errors too (a typo must not silently fall back to a default).
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/toml_reader.hpp"
#include "trueaxis/runtime/axis_interface.hpp"
#include "trueaxis/runtime/compensator_options.hpp"

namespace trueaxis::runtime {

enum class MachineKind { kVirtual, kModbus };

struct VirtualMachineConfig {
  std::string machine_file;     // sim machine TOML (examples/machines/*.toml)
  std::uint64_t seed = 1;
  double time_scale = 1.0;      // machine seconds per wall-clock second (>1: faster than real time)
  // What the virtual machine does while compensated: every axis reciprocates
  // over its travel at feed with this duty; coolant state.
  bool reciprocate = true;
  double feed_mm_min = 3000;
  double duty = 0.6;
  CoolantState coolant = CoolantState::kOff;
};

struct ModbusConfig {
  // The machine's name ([machine] name, optional): a model fitted on a machine of another name is
  // refused (the virtual machine's name is its machine file's [machine] name).
  std::string machine_name;
  std::string host = "127.0.0.1";
  int port = 1502;
  int cnc_unit_id = 1;          // the PMC window
  int first_rtd_unit_id = 2;    // ADAM-6015 style RTD modules, 7 channels each
  std::vector<std::string> axis_names = {"X", "Y", "Z"};
  std::vector<std::string> channel_names;  // names of the RTD channels in module order
  double response_timeout_s = 0.1;
};

// The browser front end of `run` (docs/web.md); the command line's --web/--users/… override it.
struct WebConfig {
  std::string listen;           // HOST:PORT, "" = no web front end
  std::string users;            // user + audit-log database
  std::string cert, key;        // TLS (PEM)
  std::string machine_id;       // "" = the command line's (default "machine")
};

struct RunConfig {
  std::string source;           // the config file path
  MachineKind machine = MachineKind::kVirtual;
  VirtualMachineConfig virtual_machine;
  ModbusConfig modbus;
  std::string model_file;
  bool model_reload = true;     // watch the model file and swap a changed model in without stopping
  // Non-empty: the model file is a data-driven thermal model (trueaxis thermal fit: mlr, ridge,
  // pso-bp, hysteresis), deployed on these axes: CNC axis → the model's error channel.
  std::map<std::string, std::string> thermal_channels;
  double period_s = 0.010;
  double temperature_period_s = 0.1;  // the temperature worker's interval (temperatures change over seconds)
  double duration_s = 0;        // 0: until SIGINT/SIGTERM
  CompensatorOptions compensator;
  std::vector<AxisInterface> axes;
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
  std::string history_db;       // history: SQLite file or postgresql:// URL (store::OpenHistorySink); "" = none
  std::string log_csv;          // CSV log of decimated cycles ("" = none)
  double record_interval_s = 1.0;  // how often a cycle is logged (alarm changes always are)
  WebConfig web;
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

// The compensator's own tables of a TOML table ([limits], [sensor_fault], [link], [channels],
// [[axis]]: docs/runtime.md), read through `r`; shared by `run` and the shop file's machines
// (docs/server.md). `period_s` is the cycle period (the CNC snapshot goes stale after 3 of them).
// `axis_lines` (optional) gets the line of each [[axis]] name, in the order of `axes`.
void ReadCompensatorTables(TomlTableReader& r, double period_s, CompensatorOptions& o, std::vector<AxisInterface>& axes,
                           std::vector<int>* axis_lines = nullptr);

// [signal] (the temperature pipeline: enabled, calibration, groups, max_disagreement_c) and
// [model] thermal_channels, read through `r` into `c` — shared by `run` and the shop file's
// machines (docs/server.md). `base`: the folder relative paths are resolved against.
void ReadSignalTable(TomlTableReader& r, const std::string& base, RunConfig& c);
void ReadThermalChannels(TomlTableReader& r, RunConfig& c);

// `model_required` false: a config without [model] is read too (what `campaign log` opens: the
// machine's channels, before there is a model).
RunConfig ParseRunConfig(const std::string& text, const std::string& source, bool model_required = true);
RunConfig ReadRunConfig(const std::string& path, bool model_required = true);

}  // namespace trueaxis::runtime
