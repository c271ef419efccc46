#pragma once
// VirtualShop: N virtual machine tools (sim::VirtualMachine), each behind its
// own MODBUS TCP terminal (the PMC window + ADAM-6015 register maps of
// docs/protocols.md through drivers/terminal_registers.hpp, the register model
// `sim serve`'s terminal uses too) on its own port base_port + i, all served by
// ONE epoll thread — `trueaxis sim shop`. Cheap enough that a 1,000-machine shop runs on
// a 2-core box beside the server (the per-machine ModbusMachineServer of
// `sim serve` uses two threads and select(): fine for one terminal, not for
// a thousand sockets in one process).
//
// One port per machine, not one port with unit ids: unit ids stop at 247 and a
// machine takes 1 + ⌈channels/7⌉ of them (3 for a VMC-850), so one port would
// hold ~80 machines; and a real shop has one terminal (one IP) per machine, so
// one connection per machine is the load the server really meets.
//
// Each machine has its own description (round robin over the list), seed and
// day: it works (every axis reciprocating) with and without coolant and idles,
// on a schedule of its own in machine time. The terminal's watchdog ramps the
// compensation to 0 when no client has written for watchdog_s.
//
// For the fault tests each terminal can be made to misbehave (TerminalFault).
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace trueaxis::sim {

class VirtualMachine;

struct VirtualShopOptions {
  std::vector<std::string> machine_files;  // descriptions (docs/machine-file.md), used round robin
  int machines = 1;
  std::string bind_address = "127.0.0.1";
  int base_port = 15000;                   // machine i listens on base_port + i
  double time_scale = 1;                   // machine seconds per wall second (cost grows with it)
  std::uint64_t seed = 1;                  // machine i uses seed + i
  double tick_s = 0.1;                     // each machine is advanced and its registers refreshed this often
  double watchdog_s = 0;                   // 0: hold; else ramp to 0 after this long without a client write
  double watchdog_ramp_um_per_s = 10;
  double max_compensation_um = 1000;
  int pmc_unit_id = 1;
  int first_rtd_unit_id = 2;
  double day_s = 4 * 3600;                 // length of one machine's work/idle schedule (machine seconds)
  bool IsValid(std::string* why) const;
};

enum class TerminalFault {
  kNone,
  kDown,          // the port refuses connections (listening socket closed)
  kSilent,        // accepts and reads, never answers
  kSlow,          // answers after fault_delay_s
  kDropMidRequest,// closes the connection when a request arrives
  kGarbage,       // answers with bytes that are not MODBUS TCP
  kWrongUnit,     // answers as another unit id
  kNoReadWrite,   // an older terminal: answers FC 23 (read/write multiple registers) with exception 0x01
};

struct VirtualShopStats {
  std::uint64_t requests = 0, exceptions = 0, connections = 0, compensation_writes = 0, ticks = 0, watchdog_steps = 0;
  double loop_cpu_s = 0;  // CPU time of the serving thread so far
};

struct VirtualMachineInfo {
  std::string name;          // "vm-0007"
  std::string description;   // machine description name
  int port = 0;
  std::vector<std::string> axes, channels;
};

class VirtualShop {
 public:
  explicit VirtualShop(VirtualShopOptions options);  // reads the descriptions (InputError)
  ~VirtualShop();
  VirtualShop(const VirtualShop&) = delete;
  VirtualShop& operator=(const VirtualShop&) = delete;

  bool Start(std::string* error);  // binds every port; false with *error when one cannot be bound
  void Stop();

  std::vector<VirtualMachineInfo> Machines() const;
  VirtualShopStats Stats() const;
  // Thread-safe; takes effect at once.
  void SetFault(std::size_t machine, TerminalFault fault, double delay_s = 0);
  // Compensation the machine's CNC applies now (µm, CNC units), and whether its watchdog is ramping.
  std::vector<double> AppliedUm(std::size_t machine) const;
  bool WatchdogRamping(std::size_t machine) const;
  // Requests terminal `machine` has received with MODBUS function code `function` (1…23).
  std::uint64_t Requests(std::size_t machine, int function) const;
  // The virtual machine behind terminal `machine`, and the mutex the serving thread holds while
  // it ticks a machine or answers a terminal: hold it while touching the machine from another
  // thread (e.g. serving the same machine through a second terminal,
  // drivers::ModbusMachineServer::ShareMachineWith).
  VirtualMachine& Machine(std::size_t machine);
  std::mutex& MachineMutex();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The shop file (docs/server.md) for the server to poll this virtual shop: one [[machine]]
// per virtual machine, every one with `model_file`.
std::string ShopFileFor(const std::vector<VirtualMachineInfo>& machines, const std::string& bind_address,
                        const std::string& model_file, const std::string& history, double period_s, int http_port);

}  // namespace trueaxis::sim
