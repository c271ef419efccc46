#pragma once
// ShopBackend: the workshop server's machines (server::Shop) on the web front end, so one front
// end serves a single machine (`run --web`, RunBackend) and the whole shop (`server --web`).
//
// Views come from the shop's thread-safe status (Shop::Snapshot / Shop::Machine): an UNAVAILABLE
// reading is shown as NaN ("—" on the page), never as the last number. Live charts come from one
// LiveRing per machine that one sampling thread fills from one Snapshot() per period (1 s), and
// the alarm list from an AlarmBook updated from the same snapshot. Operations go to the shop,
// which ramps them through each machine's limiter and records model changes with who and from
// where: a model "revision" here is a model file the machine has run (its start model and every
// file loaded since), so the page can go back to any of them; new files are loaded with
// `trueaxis server model load`. History and export read the shop's SQLite history, selecting the
// machine's "name/..." rows.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/web/alarm_book.hpp"
#include "trueaxis/web/live_ring.hpp"
#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::store {
class HistoryWriter;
}

namespace trueaxis::web {

struct ShopBackendOptions {
  std::string history_db;        // the shop's SQLite history ("" = no history charts or export)
  double sample_period_s = 1.0;  // live samples and alarm updates
  std::size_t live_capacity = 600;
};

class ShopBackend : public MonitorBackend {
 public:
  // `history` (may be null) is flushed before a history read so the newest rows show.
  ShopBackend(server::Shop& shop, store::HistoryWriter* history, ShopBackendOptions options);
  ~ShopBackend() override;  // Stop()

  void Sample(double unix_s);  // one live sample of every machine + the alarm update (the thread's step)
  void Start();                // samples every sample_period_s on its own thread
  void Stop();

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
  server::MachineStatus StatusOrThrow(const std::string& id) const;  // BackendError 404
  const server::MachineConfig& ConfigOrThrow(const std::string& id) const;
  std::string HistoryDbOrThrow() const;
  struct Figures {
    std::vector<ModelFigure> figures;  // the model file's fit summary
    std::string missing;               // why there are none ("" = shown)
  };
  Figures FiguresOf(const server::ModelInfo& model) const;

  server::Shop& shop_;
  store::HistoryWriter* history_;
  ShopBackendOptions options_;
  std::map<std::string, std::size_t> index_;  // machine name → position in the shop file
  mutable std::mutex mutex_;
  std::vector<LiveRing> live_;  // per machine, under mutex_
  mutable std::unordered_map<std::string, Figures> figures_;  // by model sha256, under mutex_
  AlarmBook alarms_;
  core::PeriodicThread worker_;  // the sampler (last: stopped before the rest goes)
};

}  // namespace trueaxis::web
