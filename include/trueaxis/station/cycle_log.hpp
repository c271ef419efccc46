#pragma once
// CycleLog: an installation's record of its cycles, kept off the real-time thread. The loop
// records into its CycleRecorder ring (every [history] record_interval_s, and every cycle whose
// alarms change); Drain() hands what was recorded to the history database (HistoryLogger over
// store::HistoryWriter, SQLite or PostgreSQL), the CSV log (CsvCycleLog) and whoever watches the
// machine (the web page's backend). Models the installation publishes are recorded the same way.
// Opened by station::Installation::OpenLog: `run`, the demo and trueaxis-hal write their history through it.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/station/csv_cycle_log.hpp"
#include "trueaxis/station/history_logger.hpp"
#include "trueaxis/station/model_loading.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::station {

// Someone who watches the installation (e.g. web::RunBackend): each drained record, each model
// published (`unix_s`: when). Both are called on the thread that drains.
struct CycleLogWatcher {
  std::function<void(const runtime::CycleRecord&)> on_record;
  std::function<void(const PublishedModel&, const std::string& sha256, const std::string& label, double unix_s)> on_model;
};

class CycleLog {
 public:
  // Opens [history] db (its folder created; throws InputError naming it) and csv. `period_s`: the
  // loop's (records are decimated to history.record_interval_s). `unix0`: the Unix time of the
  // loop's time 0 (CycleRecord::time_s; 0 when records carry Unix times).
  CycleLog(const HistoryConfig& history, std::vector<std::string> axis_names, std::vector<std::string> channel_names,
           double period_s, double unix0);
  ~CycleLog();

  runtime::CycleRecorder& recorder() { return recorder_; }  // what the loop records into
  store::HistoryWriter* writer() { return writer_.get(); }  // null without [history] db
  double unix0() const { return unix0_; }
  // What a user should know of the opening (a CSV row a killed run cut short, removed).
  const std::vector<std::string>& notes() const { return notes_; }

  // Adds a watcher; it is told the model in force at once (when there is one).
  void Watch(CycleLogWatcher watcher);
  // Every record the loop handed over since the last call, to the history, the CSV log, the
  // watchers and then `each`. Returns how many.
  std::size_t Drain(const std::function<void(const runtime::CycleRecord&)>& each = {});
  // One record, not through the ring (the demo's sampled cycles).
  void Log(const runtime::CycleRecord& record);
  // A model was published: to the history (`note`) and the watchers (`label`).
  void ModelPublished(const PublishedModel& model, const std::string& sha256, const std::string& note,
                      const std::string& label, double unix_s);
  void Flush();  // the CSV log to disk (at most this much is lost to a kill -9)
  // After the loop stopped: drains, flushes, closes the history (idempotent).
  void Close();
  std::uint64_t Dropped() const { return recorder_.Dropped(); }  // records lost to a slow consumer

 private:
  struct InForce {
    PublishedModel model;
    std::string sha256, label;
    double unix_s = 0;
  };
  runtime::CycleRecorder recorder_;
  double unix0_;
  std::unique_ptr<store::HistoryWriter> writer_;
  std::unique_ptr<HistoryLogger> history_;
  std::unique_ptr<CsvCycleLog> csv_;
  std::vector<CycleLogWatcher> watchers_;
  std::optional<InForce> in_force_;
  std::vector<std::string> notes_;
  runtime::CycleRecord record_;
};

}  // namespace trueaxis::station
