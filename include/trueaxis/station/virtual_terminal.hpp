#pragma once
// The virtual machine tool behind its MODBUS TCP terminal (PMC window + ADAM-6015 RTD modules,
// docs/protocols.md), in (scaled) real time: what `trueaxis sim serve` runs, and the demo's
// terminal with --modbus. The CLI only parses options and prints the status.
//
//   station::VirtualTerminal t(config, server_options);   // builds the machine, starts its program
//   t.Start();                                             // binds; throws when the port is taken
//   auto s = t.Status();                                   // from any thread
#include <atomic>
#include <cstdint>
#include <optional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/sim/laser_interferometer.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::station {

// The virtual machine a config names, with its working program started (every axis reciprocating
// over 10…90 % of its travel at the config's feed and duty, or idle) and its coolant state.
// Throws InputError on a bad machine file.
std::unique_ptr<sim::VirtualMachine> OpenVirtualMachine(const VirtualMachineConfig& config);
// Starts the config's working program on `vm` (reciprocate, or nothing for idle).
void StartProgram(sim::VirtualMachine& vm, const VirtualMachineConfig& config);

// A laser interferometer set up on one axis of the served machine (`sim serve --laser-axis`): what
// a user gets from the laser software on a real machine — a test file with its start date (the
// wall clock) and a time per point, and nothing of the machine's own sensors. The machine stands
// until the first test (the cold state), then runs its program; every `every_s` machine seconds
// the program stops for a test. A test runs in machine time at once; the machine stands for as
// long in scaled wall time (before the test, as long as the last one took: the channels show the
// machine as the test starts), so its clock stays the wall clock × the time scale.
struct ServedLaser {
  std::string axis;
  std::string out_dir;       // <axis>_laser_<nnn>.csv, each written whole (renamed into place)
  double first_s = 600;      // machine seconds before the first (cold) test
  double every_s = 1800;     // machine seconds from one test's start to the next
  int runs = 2;
  double spacing_mm = 50;
  int count = 0;             // tests in all (0: until stopped)
};

// What the terminal's machine shows, copied on the machine thread after each exchange.
struct VirtualTerminalStatus {
  double machine_time_s = 0;
  std::string iso_time;
  std::string coolant;
  std::vector<double> commanded_mm, actual_mm, error_um, correction_um;  // per axis
  std::vector<double> sensor_c;                                          // per channel
};

class VirtualTerminal {
 public:
  VirtualTerminal(const VirtualMachineConfig& config, drivers::ModbusMachineServerOptions server);
  ~VirtualTerminal();  // Stop()
  VirtualTerminal(const VirtualTerminal&) = delete;
  VirtualTerminal& operator=(const VirtualTerminal&) = delete;

  // Binds and starts the terminal; from here on its machine thread owns the machine.
  // Throws std::runtime_error when the port cannot be bound.
  void Start();
  void Stop();
  // Before Start(); throws InputError naming the option when the axis is unknown.
  void SetLaser(const ServedLaser& laser);
  int LaserTests() const;  // tests written so far (any thread)

  VirtualTerminalStatus Status() const;
  drivers::ModbusMachineServerStats Stats() const { return server_->Stats(); }
  std::size_t RtdModuleCount() const { return server_->RtdModuleCount(); }
  const drivers::ModbusMachineServerOptions& options() const { return server_->options(); }
  // Immutable facts of the machine (name, axes, channels): safe from any thread.
  const sim::MachineDescription& description() const { return vm_->description(); }
  const std::vector<std::string>& axis_names() const { return axis_names_; }
  const std::vector<std::string>& channel_names() const { return channel_names_; }

 private:
  void Snapshot();  // machine thread (or before Start)
  void Advance(double wall_elapsed_s);  // machine thread
  void TakeLaserTest();                 // machine thread

  VirtualMachineConfig config_;
  std::optional<ServedLaser> laser_;
  std::unique_ptr<sim::LaserInterferometer> interferometer_;
  std::size_t laser_axis_ = 0;
  double next_laser_s_ = 0, pause_s_ = 0;
  bool laser_due_ = false;         // the machine stands before the test
  double laser_wall_start_ = 0;    // wall clock as the test was due: the file's date
  double last_laser_s_ = 0;        // the last test's machine seconds
  std::atomic<int> laser_tests_{0};

  std::unique_ptr<sim::VirtualMachine> vm_;
  std::unique_ptr<drivers::ModbusMachineServer> server_;
  std::vector<std::string> axis_names_, channel_names_;
  std::vector<hw::RawTemperature> temps_;
  mutable std::mutex mu_;
  VirtualTerminalStatus status_;
};

}  // namespace trueaxis::station
