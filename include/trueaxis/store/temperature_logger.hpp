#pragma once
// TemperatureLogger: glue between a TemperatureMonitor and the history
// database, for the real-time loop. After each monitor.Update() call Log():
//   - every channel's reading (raw, filtered, status) is pushed at most once
//     per `log_period_s` (0 = every reading), and always when its status changes;
//   - a status change also pushes an alarm ("fault" when a channel leaves ok,
//     "info" when it returns), with the status names of docs/signal.md.
// No allocation, no lock: it only formats into fixed buffers and pushes to
// the writer's lock-free queue. Drops (queue full) are counted by the writer.
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/signal/temperature_monitor.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::store {

struct TemperatureLoggerOptions {
  double log_period_s = 1.0;  // 0: every reading
  bool alarms_on_status_change = true;
  bool IsValid(std::string* why) const;
};

class TemperatureLogger {
 public:
  TemperatureLogger(HistoryWriter& writer, const signal::TemperatureMonitor& monitor,
                    TemperatureLoggerOptions options = {});
  void Log(double time_s) noexcept;
  std::uint64_t readings_pushed() const { return readings_; }
  std::uint64_t alarms_pushed() const { return alarms_; }

 private:
  HistoryWriter& writer_;
  const signal::TemperatureMonitor& monitor_;
  TemperatureLoggerOptions options_;
  std::vector<double> last_logged_s_;  // per channel; sized once
  std::uint64_t readings_ = 0, alarms_ = 0;
};

}  // namespace trueaxis::store
