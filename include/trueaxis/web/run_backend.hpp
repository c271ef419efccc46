#pragma once
// RunBackend: the MonitorBackend of one machine under `trueaxis run`. The run's own loop (its
// main thread) hands every CycleRecord it drains to OnRecord and every model it publishes to
// OnModelPublished; HTTP workers read the copies kept here under a mutex and operate the running
// compensator (axis enable through its atomic switches — the limiter ramps; coolant through the
// CoolantOverrideLink in front of the CNC; model revisions through PublishModel). History and
// export read the run's history database (read-only connections; the run's writer keeps writing).
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/station/model_loading.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/web/alarm_book.hpp"
#include "trueaxis/web/coolant_override_link.hpp"
#include "trueaxis/web/live_ring.hpp"
#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

struct RunBackendOptions {
  std::string machine_id = "machine";  // [A-Za-z0-9_.-]
  std::string machine_name;            // shown; "" = the id
  std::string history_db;              // "" = no history charts or export
  std::string iso_dir;                 // laser test pairs for the ISO figures ("" = the fit summary's)
  double unix0 = 0;                    // Unix time of the loop's time 0 (CycleRecord::time_s)
  std::size_t live_capacity = 600;
};

class RunBackend : public MonitorBackend {
 public:
  // `coolant` may be null (no override possible); `writer` (may be null) gets model changes.
  RunBackend(runtime::Compensator& compensator, CoolantOverrideLink* coolant, store::HistoryWriter* writer,
             RunBackendOptions options);

  // ---- the run's loop thread ----
  void OnRecord(const runtime::CycleRecord& record);
  // Any model the run publishes (seed-000 or a deployed thermal model, station::PublishModelFile).
  void OnModelPublished(station::PublishedModel model, const std::string& sha256, const std::string& label,
                        double unix_s);

  // ---- MonitorBackend ----
  std::string Describe() const override;
  std::vector<MachineSummary> ListMachines() const override;
  MachineDetail Machine(const std::string& id) const override;
  LiveSeries Live(const std::string& id, std::uint64_t after_sequence, std::size_t max_samples) const override;
  HistorySeries History(const std::string& id, double from_unix_s, double to_unix_s, std::size_t max_points) const override;
  std::vector<AlarmEntry> Alarms(std::size_t limit) const override;
  void SetAxisEnabled(const Actor& who, const std::string& id, const std::string& axis, bool enabled) override;
  void AcknowledgeAlarm(const Actor& who, const std::string& alarm_id) override;
  void SetCoolantOverride(const Actor& who, const std::string& id, const std::string& state) override;
  void LoadModelRevision(const Actor& who, const std::string& id, const std::string& revision) override;
  std::string RollbackModel(const Actor& who, const std::string& id) override;
  ExportFile Export(const std::string& id, double from_unix_s, double to_unix_s, ExportFormat format) const override;

 private:
  struct Loaded {
    station::PublishedModel model;
    ModelRevision info;
    std::vector<ModelFigure> figures;
  };
  void CheckId(const std::string& id) const;
  MachineSummary Summary() const;  // the machine now, with the coolant override
  void Publish(const Loaded& loaded, const std::string& note);  // throws BackendError 409 on a model that does not bind
  std::string HistoryDbOrThrow() const;

  runtime::Compensator& compensator_;
  CoolantOverrideLink* coolant_;
  store::HistoryWriter* writer_;
  RunBackendOptions options_;
  std::vector<std::string> axes_, channels_;
  std::vector<ModelFigure> iso_figures_;
  mutable std::mutex mutex_;
  MachineSummary summary_;
  LiveRing live_;
  std::vector<Loaded> loaded_;        // every model this run has published, oldest first
  std::vector<std::size_t> in_use_;   // indices into loaded_: the revisions in use, current last
  AlarmBook alarms_;
};

}  // namespace trueaxis::web
