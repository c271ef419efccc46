#include "trueaxis/store/temperature_logger.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace trueaxis::store {

bool TemperatureLoggerOptions::IsValid(std::string* why) const {
  if (!(log_period_s >= 0) || !std::isfinite(log_period_s)) {
    if (why) *why = "log_period_s must be a finite value >= 0";
    return false;
  }
  return true;
}

TemperatureLogger::TemperatureLogger(HistoryWriter& writer, const signal::TemperatureMonitor& monitor,
                                     TemperatureLoggerOptions options)
    : writer_(writer), monitor_(monitor), options_(options), last_logged_s_(monitor.ChannelCount(), NAN) {
  std::string why;
  if (!options_.IsValid(&why)) throw std::invalid_argument("TemperatureLogger options: " + why);
}

void TemperatureLogger::Log(double time_s) noexcept {
  using signal::ChannelStatus;
  for (std::size_t i = 0; i < monitor_.ChannelCount(); ++i) {
    const auto& r = monitor_.reading(i);
    const std::string& name = monitor_.ChannelName(i);
    const bool due = std::isnan(last_logged_s_[i]) || options_.log_period_s <= 0 ||
                     time_s - last_logged_s_[i] >= options_.log_period_s - 1e-9 ||  // tolerate clock sums like 10 x 0.1
                      time_s < last_logged_s_[i];
    if (due || r.status_changed) {
      writer_.PushTemperature(time_s, name, r.raw_c, r.filtered_c, signal::ChannelStatusName(r.status));
      last_logged_s_[i] = time_s;
      ++readings_;
    }
    if (options_.alarms_on_status_change && r.status_changed) {
      // Formatted into a fixed buffer: no allocation in the cycle.
      char message[160];
      const auto out = fmt::format_to_n(message, sizeof(message) - 1, "{} -> {}: {}", name,
                                        signal::ChannelStatusName(r.status), signal::ChannelStatusDescription(r.status));
      *out.out = '\0';
      const bool ok = r.status == ChannelStatus::kOk;
      writer_.PushAlarm(time_s, ok ? "info" : "fault", name, message);
      ++alarms_;
    }
  }
}

}  // namespace trueaxis::store
