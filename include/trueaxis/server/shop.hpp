#pragma once
// server::Shop: the workshop server (seed 003). Event-loop threads ([server]
// poll_threads, 1 by default; machine i belongs to thread i mod K for good,
// each thread with its own epoll set, timers and counters) poll every
// machine's terminal over MODBUS TCP (epoll, non-blocking sockets, its own
// MBAP framing — libmodbus' select() breaks at socket numbers ≥ 1024 and
// its context is not thread-safe), run each machine's compensator with the
// same pure step as `trueaxis run` (runtime::Step: signal chain conditioning,
// limiter, faults) and writes the corrections back with one FC 16.
//
// Per machine and period: FC 04 PMC window → FC 03 AI values of each ADAM-6015
// → Step → FC 16 compensation (this write also refreshes the terminal's
// watchdog). One request in flight per terminal, staggered start, a timeout per
// request, reconnect with exponential backoff. A terminal that fails only
// makes its own machine's values UNAVAILABLE (MTConnect): never a stale number.
// After every (re)connect the limiter starts from the compensation the CNC
// applies now (input registers 16+8a+4..5), so a server restart never jumps.
//
// Thread-safe API for the CLI, the HTTP control API and the web front end:
// Snapshot() / Machine(), LoadModel / Rollback (ramped through the limiter,
// recorded with who, when, old and new revision), SetAxisEnabled,
// AcknowledgeAlarms, SetCoolantOverride. docs/server.md.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/server/shop_config.hpp"

namespace trueaxis::store {
class HistoryWriter;
}

namespace trueaxis::server {

// A value that may be UNAVAILABLE (std::nullopt): the link is down or the
// terminal reports its data stale.
using Reading = std::optional<double>;

struct AxisView {
  std::string name;
  Reading position_mm;      // as the CNC reports it
  Reading applied_um;       // compensation the CNC applies now (CNC units), as the terminal reports
  double target_um = 0;     // what the model asks for (physical µm; NaN = hold)
  double output_um = 0;     // the limiter's output the server last handed out (physical µm)
  bool enabled = true;      // the server's switch for this axis
  // How the compensator treats it now (runtime::AxisCompensationState): full, fallback_model
  // (a sensor of the model lost), geometric, disabled or link_lost.
  std::string state = "link_lost";
};

struct ChannelView {
  std::string name;
  Reading temp_c;           // last reading (UNAVAILABLE when the module did not answer)
  std::string health;       // ok | held | lost (the compensator's verdict)
};

struct ModelInfo {
  std::string file;
  std::string sha256;
  int revision = 0;         // the model file's own revision
  std::uint64_t slot = 0;   // position in this machine's model list (rollback goes back one)
};

struct MachineStatus {
  std::string name;
  std::string endpoint;         // host:port
  bool connected = false;
  double last_good_read_unix_s = 0;  // 0: never
  std::uint32_t alarms = 0;          // runtime::Alarm bits now
  std::string alarm_names;           // "link_read|stale_input"
  std::uint32_t unacknowledged = 0;  // alarms raised since the last AcknowledgeAlarms
  std::string last_fault;            // why the link last failed ("" never)
  std::uint64_t cycles = 0, complete_cycles = 0, faults = 0, connects = 0, overruns = 0;
  double last_latency_ms = 0;        // last read → write acknowledged
  std::string coolant;               // as read (or overridden)
  std::optional<std::string> coolant_override;
  ModelInfo model;
  std::vector<AxisView> axes;
  std::vector<ChannelView> channels;
};

struct ModelChange {
  std::string machine, user, from;
  double time_unix_s = 0;
  ModelInfo old_model, new_model;
  std::string action;  // load | rollback
};

struct ShopStats {
  std::uint64_t cycles = 0;           // cycle ticks over all machines
  std::uint64_t complete_cycles = 0;  // read → step → write acknowledged
  std::uint64_t faults = 0;
  std::uint64_t overruns = 0;         // a tick found the previous cycle still in flight
  // read → write of complete cycles since the last ResetLatency (every loop thread's, merged): p50 and p99 are the upper edge of
  // their bucket (buckets 6 % wide), max exact
  double latency_p50_ms = 0, latency_p99_ms = 0, latency_max_ms = 0;
  std::uint64_t latency_samples = 0;
  std::vector<std::pair<double, std::uint64_t>> latency_histogram;  // (bucket's upper edge ms, count), non-empty buckets
  std::uint64_t history_dropped = 0;
  double loop_cpu_s = 0;              // CPU time of the event-loop threads so far (summed)
  int poll_threads = 0;               // event-loop threads (machine i is polled by thread i mod poll_threads)
};

class Shop {
 public:
  // Loads every machine's model (InputError naming the machine on a model that does not fit).
  // `history` may be null (no history); it must outlive the shop.
  Shop(ShopConfig config, store::HistoryWriter* history);
  ~Shop();  // Stop()
  Shop(const Shop&) = delete;
  Shop& operator=(const Shop&) = delete;

  void Start();
  void Stop();

  std::vector<MachineStatus> Snapshot() const;
  std::optional<MachineStatus> Machine(const std::string& name) const;
  // Machine i (0 .. MachineCount() − 1, the shop file's order): one status at a time, for answers
  // about every machine that should not hold every status at once.
  std::size_t MachineCount() const;
  MachineStatus MachineAt(std::size_t i) const;
  std::vector<std::string> MachineNames() const;
  ShopStats Stats() const;
  void ResetLatency();

  // Model changes on the server only. Throw InputError on an unknown machine or a model
  // that does not bind to the machine (the running model stays). The switch ramps through
  // the limiter. Recorded in the history (model change) and the audit log.
  ModelChange LoadModel(const std::string& machine, const std::string& model_file, const std::string& user,
                        const std::string& from);
  ModelChange Rollback(const std::string& machine, const std::string& user, const std::string& from);
  std::vector<ModelChange> ModelChanges(const std::string& machine) const;

  void SetAxisEnabled(const std::string& machine, const std::string& axis, bool enabled, const std::string& user);
  void AcknowledgeAlarms(const std::string& machine, const std::string& user);
  // The coolant state the model uses instead of the one read (std::nullopt: follow the CNC).
  void SetCoolantOverride(const std::string& machine, std::optional<CoolantState> coolant, const std::string& user);

  const ShopConfig& config() const { return config_; }

 private:
  struct Impl;
  ShopConfig config_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace trueaxis::server
