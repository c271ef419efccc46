#pragma once
// Installation: one machine as the compensator runs it, wherever its hardware
// is. The same assembly serves `trueaxis run`, the demo, the LinuxCNC HAL
// programs and every machine of the workshop server (docs/ARCHITECTURE.md):
//
//   run config ─► hardware: hw::CncLink + raw hw::TemperatureSource (their lifecycle is the owner's)
//              ─► the one temperature pipeline (signal::MonitoredTemperatureSource: calibration,
//                 filters, redundant groups, the one judge of every value) — MakeTemperaturePipeline
//              ─► runtime::Compensator (the pure step on explicit state, pick-up without a jump)
//              ◄─ the model: composite, or data-driven thermal models on [model] thermal_channels;
//                 loaded, reloaded, rolled back                     — model_loading.hpp
//              ─► its record (OpenLog, [history]): history database, CSV log, watchers such as the
//                 web page; cycles and model changes                — cycle_log.hpp
//
// Driven two ways, with the same code in between:
//   - by its own periodic loop: runtime::LoopRunner over compensator(), link(), temperatures()
//     (`run`, the demo, the HAL programs);
//   - by one event thread serving many machines: the workshop server decodes a machine's
//     registers into its asynchronous hardware and calls Cycle() when that machine's reads are
//     complete, writes command() and calls CommitWrite() when the write is answered. No thread
//     per machine; Cycle/CommitWrite allocate nothing.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/io_snapshot.hpp"
#include "trueaxis/signal/monitored_temperature_source.hpp"
#include "trueaxis/station/cycle_log.hpp"
#include "trueaxis/station/installation_config.hpp"
#include "trueaxis/station/model_loading.hpp"

namespace trueaxis::station {

class Installation {
 public:
  // `raw_temperatures`: the hardware's channels; the pipeline is put in front of them (its filter
  // with [signal] enabled, the default), timed by `clock_s`. `machine_name`: a model fitted on a machine of
  // another name is refused ("" = not compared). Loads the config's model (InputError naming the
  // config or the model file when it does not fit the machine); a config without a model file
  // starts without one (the caller publishes a model built in memory, as the demo does).
  Installation(InstallationConfig config, hw::CncLink& link, hw::TemperatureSource& raw_temperatures,
               std::function<double()> clock_s, std::string machine_name);

  const InstallationConfig& config() const { return config_; }
  runtime::Compensator& compensator() { return *compensator_; }
  const runtime::Compensator& compensator() const { return *compensator_; }
  hw::CncLink& link() { return link_; }
  // What the compensator reads: the pipeline, the one temperature judge (with [signal] enabled =
  // false its filter is off, its fault rules still apply).
  signal::JudgedTemperatureSource& temperatures() { return *pipeline_; }
  signal::MonitoredTemperatureSource* pipeline() { return pipeline_.get(); }
  const std::vector<std::string>& warnings() const { return warnings_; }

  // ---- the per-cycle entry (one thread; no allocation) ----
  // Reads the CNC link and — when `read_temperatures` (new values are there, or the source
  // failed) — the pipeline, then steps. The caller writes command() (or skips the write while
  // compensator().PickUpPending()) and reports the outcome with CommitWrite().
  const runtime::CycleStatus& Cycle(double now_s, bool read_temperatures = true);
  const runtime::CncCommand& command() const { return compensator_->command(); }
  const runtime::CycleStatus& CommitWrite(bool write_ok) { return compensator_->CommitWrite(write_ok); }
  const runtime::CncSnapshot& cnc() const { return cnc_; }
  const runtime::TemperatureSnapshot& temperature_snapshot() const { return temperatures_; }

  // ---- models (any thread but the cycle's) ----
  const PublishedModel& model() const { return model_; }
  // Reads `model_file` as this installation's model (composite, or thermal on the config's
  // thermal_channels), checks it against the machine and publishes it (the loop ramps to it).
  // Throws InputError; the running model stays in force then.
  const PublishedModel& LoadModel(const std::string& model_file);
  // The same checks without publishing (to record the change first, then Publish it).
  PublishedModel ReadModel(const std::string& model_file) const;
  // Publishes a model loaded before (a rollback).
  void Publish(const PublishedModel& model, const std::string& label);
  // Reloads the config's model file when it changed since it was loaded (model_reload): the new
  // model, or nullopt when unchanged. Throws InputError when the changed file is refused. A
  // reloaded model is recorded in the log (when open).
  std::optional<PublishedModel> ReloadIfChanged();

  // ---- its record (the thread that drains; not the cycle's) ----
  // Opens the record of this installation's cycles ([history]: database, CSV log; throws
  // InputError naming them) and records the config's model in force as loaded at `unix0`, the
  // Unix time of the loop's time 0. A loop driving this installation records into
  // log()->recorder(); the owner drains it (CycleLog::Drain) and closes it after the loop stopped.
  CycleLog& OpenLog(const HistoryConfig& history, double unix0);
  CycleLog* log() { return log_.get(); }

 private:
  InstallationConfig config_;
  hw::CncLink& link_;
  hw::TemperatureSource& raw_;
  std::string machine_name_;
  std::vector<std::string> warnings_;
  std::unique_ptr<signal::MonitoredTemperatureSource> pipeline_;
  std::unique_ptr<runtime::Compensator> compensator_;
  PublishedModel model_;
  std::optional<std::filesystem::file_time_type> model_mtime_;
  std::unique_ptr<CycleLog> log_;
  runtime::CncSnapshot cnc_;
  runtime::TemperatureSnapshot temperatures_;
  std::uint64_t cnc_reads_ = 0, temperature_reads_ = 0;
};

}  // namespace trueaxis::station
