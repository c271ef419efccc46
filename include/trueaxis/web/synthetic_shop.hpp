#pragma once
// SyntheticShop: a MonitorBackend of N made-up machines for the demo shop and the web load test
// (until the workshop server's server::Shop is bound to the web front end). Each machine has
// three axes and four temperature channels that follow a slow warm-up plus a per-machine daily
// swing; the corrections follow the temperatures; a few machines carry alarms or are
// disconnected. Values come from a formula of time, so history is available for any range.
// Tick() advances every machine to a time (a test calls it; Start() runs it at a period).
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/web/alarm_book.hpp"
#include "trueaxis/web/live_ring.hpp"
#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

class SyntheticShop : public MonitorBackend {
 public:
  explicit SyntheticShop(std::size_t machine_count, std::size_t live_capacity = 600);
  ~SyntheticShop() override;  // Stop()

  void Tick(double unix_s);
  void Start(double period_s);  // ticks on its own thread at the wall clock
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
  struct Machine_ {
    MachineSummary summary;
    std::vector<std::string> revision_stack;  // loaded revisions, current last
    LiveRing live;
    double phase = 0;       // per-machine offset of the daily swing
    double gain = 1;        // per-machine µm per °C scale
  };
  std::size_t Index(const std::string& id) const;  // BackendError 404
  void Evaluate(const Machine_& m, double unix_s, std::vector<double>& temp_c, std::vector<double>& corr_um) const;

  static const std::vector<std::string> kAxes, kChannels;
  double start_unix_s_ = 0;
  mutable std::shared_mutex mutex_;
  std::vector<Machine_> machines_;
  AlarmBook alarms_;
  core::PeriodicThread ticker_;  // last: stopped first
};

}  // namespace trueaxis::web
