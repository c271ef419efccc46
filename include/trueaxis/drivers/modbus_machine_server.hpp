#pragma once
// ModbusMachineServer: puts any hw::CncLink + hw::TemperatureSource on the
// network as a workshop terminal would (seed 003: the compensation terminal
// answers MODBUS TCP requests addressed to its machine's id):
//   unit id `pmc_unit_id` (default 1)        the CNC's PMC window (pmc_window_map.hpp)
//   unit ids first_rtd_unit_id.. (default 2..) one Advantech ADAM-6015 per 7
//                                            temperature channels (adam6015_map.hpp)
// all on one TCP port. docs/protocols.md lists every register.
//
// Threads: a network thread serves any number of clients (up to max_clients)
// with select() and per-connection frame assembly (a client stalled inside a
// frame delays nobody); a machine thread is the only one that touches the CncLink and
// TemperatureSource. They meet in a register image guarded by one mutex that
// neither holds across I/O, so a slow or stalled client never delays the
// machine and a slow machine never blocks the network. Compensation written
// by a client wakes the machine thread at once (no waiting for the period).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/pmc_window_map.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::drivers {

struct ModbusMachineServerOptions {
  std::string bind_address = "127.0.0.1";  // loopback unless asked otherwise
  int port = 1502;                          // 502 needs root; 1502 is the usual unprivileged stand-in
  int pmc_unit_id = pmc::kDefaultUnitId;
  int first_rtd_unit_id = 2;                // ADAM module k answers unit first_rtd_unit_id + k
  std::uint16_t rtd_range_code = adam6015::kDefaultRangeCode;  // initial type code of every channel
  double machine_period_s = 0.005;          // machine exchange period (read state, forward compensation)
  double max_abs_compensation_um = 1000.0;  // larger writes are refused with ILLEGAL DATA VALUE
  bool initial_enable = true;               // PMC enable register at start
  int max_clients = 16;                     // when full, the longest-silent connection makes room for a new one
  double idle_timeout_s = 10.0;             // a connection silent this long is closed (0 = never)
  // Link-loss behaviour on the machine side: with watchdog_s > 0, when no
  // client has written a PMC holding register for that long, the compensation
  // ramps to 0 at watchdog_ramp_um_per_s (never a jump). 0 = hold the last value.
  double watchdog_s = 0.0;
  double watchdog_ramp_um_per_s = 10.0;

  bool IsValid(std::string* why) const;
};

struct ModbusMachineServerStats {
  std::uint64_t requests = 0;          // requests answered (normal or exception)
  std::uint64_t exceptions = 0;        // of which exception responses
  std::uint64_t connections = 0;       // connections accepted
  std::uint64_t refused_connections = 0;  // socket number beyond what select() takes
  std::uint64_t evicted_connections = 0;  // closed (longest silent) to let a new client in
  std::uint64_t idle_disconnects = 0;     // closed after idle_timeout_s of silence
  std::uint64_t exchanges = 0;         // machine exchanges (= heartbeat)
  std::uint64_t compensation_writes = 0;  // vectors forwarded to CncLink::WriteCompensation
  std::uint64_t watchdog_steps = 0;       // exchanges in which the watchdog ramped the compensation
  int clients = 0;                     // connected now
  std::string BriefReport() const;
};

// The terminal's unit-id layout: the RTD modules (adam6015::kChannelCount channels each, unit ids
// from first_rtd_unit_id on) must stay within MODBUS's 247 and, with a CNC, miss pmc_unit_id. The
// reason when they do not, else nullopt — for a caller to name its own option or config key before
// Start() (which refuses the same layout with the same text).
std::optional<std::string> UnitIdLayoutProblem(const ModbusMachineServerOptions& options, std::size_t channel_count,
                                               bool has_cnc);

class ModbusMachineServer {
 public:
  // Called on the machine thread before each exchange with the wall-clock
  // seconds since the previous one: `sim serve` advances its virtual machine here.
  using AdvanceFn = std::function<void(double wall_elapsed_s)>;

  // Either source may be null (then its units are absent). Both must outlive
  // the server and are used only from the machine thread while it runs.
  ModbusMachineServer(hw::CncLink* cnc, hw::TemperatureSource* temperatures,
                      ModbusMachineServerOptions options = {});
  ~ModbusMachineServer();  // Stop()
  ModbusMachineServer(const ModbusMachineServer&) = delete;
  ModbusMachineServer& operator=(const ModbusMachineServer&) = delete;

  void SetAdvance(AdvanceFn advance);  // before Start()
  // For an owner that also drives the machine from its own thread (the demo moves its
  // virtual machine while a compensator reaches it over MODBUS): the machine thread holds
  // `machine_mutex` around each exchange with the CNC and the sensors, so the owner locks
  // the same mutex while it touches the machine. Before Start(); the mutex outlives the server.
  void ShareMachineWith(std::mutex* machine_mutex);
  // Binds and starts both threads. False with *error when the options are
  // invalid or the port cannot be bound (in use): the caller may retry another.
  bool Start(std::string* error);
  // Stops both threads and closes every socket; idempotent.
  void Stop();
  bool running() const { return running_.load(); }

  ModbusMachineServerStats Stats() const;
  std::size_t RtdModuleCount() const;
  const ModbusMachineServerOptions& options() const { return options_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ModbusMachineServerOptions options_;
  std::atomic<bool> running_{false};
};

}  // namespace trueaxis::drivers
