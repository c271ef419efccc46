#pragma once
// SiteConfig: the TOML file of `trueaxis run --config FILE` (docs/runtime.md), also read by the
// demo's MODBUS wiring, `campaign log` and the LinuxCNC HAL programs. It holds one installation
// (station::InstallationConfig: loop, compensator, [signal], [model]) and where that installation
// is deployed — the machine ([machine]: the virtual machine in process, or a CNC terminal and RTD
// modules over MODBUS TCP), its history ([history]) and its web page ([web]). None of the
// deployment reaches the pure runtime.
// Every error is an InputError naming the file, line and key; unknown keys are errors too (a typo
// must not silently fall back to a default).
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/station/installation_config.hpp"

namespace trueaxis::station {

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

// [history]: where the installation's cycles are recorded (station::CycleLog).
struct HistoryConfig {
  std::string db;               // SQLite file or postgresql:// URL (store::OpenHistorySink); "" = none
  std::string csv;              // CSV log of decimated cycles ("" = none)
  double record_interval_s = 1.0;  // how often a cycle is logged (alarm changes always are)
};

// The browser front end of `run` (docs/web.md); the command line's --web/--users/… override it.
struct WebConfig {
  std::string listen;           // HOST:PORT, "" = no web front end
  std::string users;            // user + audit-log database
  std::string cert, key;        // TLS (PEM)
  std::string machine_id;       // "" = the command line's (default "machine")
};

struct SiteConfig {
  InstallationConfig installation;  // its source and key lines are the whole file's
  MachineKind machine = MachineKind::kVirtual;
  VirtualMachineConfig virtual_machine;
  ModbusConfig modbus;
  HistoryConfig history;
  WebConfig web;

  const std::string& source() const { return installation.source; }
  int LineOf(const std::string& key) const { return installation.LineOf(key); }
};

// `model_required` false: a config without [model] is read too (what `campaign log` opens: the
// machine's channels, before there is a model).
SiteConfig ParseSiteConfig(const std::string& text, const std::string& source, bool model_required = true);
SiteConfig ReadSiteConfig(const std::string& path, bool model_required = true);

}  // namespace trueaxis::station
