#pragma once
// The wiring shared by `trueaxis run`, the demo and `sim serve`: open the
// hardware a run configuration names (the virtual machine in process, or a CNC
// terminal + ADAM-6015 RTD modules over MODBUS TCP), and put the one
// temperature pipeline (signal::MonitoredTemperatureSource, on by default) in
// front of the compensator. The CLI files only parse options (docs/runtime.md).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/no_temperature_source.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::station {

// The MODBUS clients of one terminal: the PMC window and the RTD modules
// (unit ids first_rtd_unit_id, +1, ... one per 7 channels; none without channel names). Not connected yet.
struct ModbusClients {
  std::unique_ptr<drivers::ModbusCncLink> cnc;
  std::unique_ptr<drivers::ModbusTemperatureSource> temperatures;
};
// Throws InputError(source, ...) on options the clients refuse. `heartbeat_stale_after_s`: the
// terminal's heartbeat frozen this long is a link fault.
ModbusClients MakeModbusClients(const ModbusConfig& config, const std::string& source,
                                double heartbeat_stale_after_s = 0.5);

// The hardware behind the loop; owns whichever implementation the config names.
struct Machine {
  std::unique_ptr<sim::VirtualMachine> vm;
  ModbusClients modbus;
  std::unique_ptr<hw::NoTemperatureSource> no_temperatures;       // MODBUS without channels
  std::unique_ptr<signal::MonitoredTemperatureSource> monitored;  // the judge: what the compensator reads
  hw::CncLink* link = nullptr;
  hw::TemperatureSource* source = nullptr;  // the raw temperatures (behind `monitored`)
  std::function<void(double)> advance;     // in-process machine: moved on by the loop thread
  std::string description;
  // The machine's name, which a model must have been fitted on: the virtual machine's (its machine
  // file's [machine] name), a MODBUS machine's [machine] name; "" when the config names none.
  std::string name;
  std::vector<std::string> warnings;       // e.g. terminal not reachable yet, calibration unmatched

  // The clock the temperature pipeline judges rates by: the machine's own for the in-process
  // virtual machine, the steady clock (seconds from now) otherwise.
  std::function<double()> Clock() const;
  void Close();  // deactivates the hardware (hw lifecycle); the loop must be stopped
};

// Opens the machine of `config` — configures and activates its hardware (hw/lifecycle.hpp) — (throws InputError naming the config on bad settings) and
// the temperature pipeline in front of it (its filter only with [signal] enabled, the default; its
// fault rules always) — timed by the machine's clock for the in-process virtual machine, by the
// steady clock otherwise.
// `with_pipeline` false: the raw hardware only (station::Installation puts the pipeline in front).
Machine OpenMachine(const SiteConfig& config, bool with_pipeline = true);

// The one temperature pipeline of a configuration in front of `raw`: the judge's options
// (TemperatureJudgeOptions: fault limits, redundant groups, filter on or off), calibration from [signal]
// (throws InputError naming the config on a group channel the source lacks or a missing
// calibration file; a calibration entry matching no channel is a warning).
std::unique_ptr<signal::MonitoredTemperatureSource> MakeTemperaturePipeline(const InstallationConfig& config,
                                                                            hw::TemperatureSource& raw,
                                                                            std::function<double()> clock_s,
                                                                            std::vector<std::string>* warnings);

}  // namespace trueaxis::station
