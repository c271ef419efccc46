#include "trueaxis/station/history_logger.hpp"

#include <array>

#include <fmt/format.h>

namespace trueaxis::station {

const char* ChannelHealthName(ChannelHealth h) {
  switch (h) {
    case ChannelHealth::kOk: return "ok";
    case ChannelHealth::kHeld: return "held";
    case ChannelHealth::kLost: return "lost";
  }
  return "?";
}

HistoryLogger::HistoryLogger(store::HistoryWriter& writer, std::vector<std::string> axis_names,
                             std::vector<std::string> channel_names, double time_offset_s,
                             std::string alarm_source)
    : writer_(writer),
      axis_names_(std::move(axis_names)),
      channel_names_(std::move(channel_names)),
      offset_s_(time_offset_s),
      alarm_source_(std::move(alarm_source)) {}

void HistoryLogger::Log(const CycleRecord& r) {
  const double t = r.time_s + offset_s_;
  for (std::size_t i = 0; i < r.channel_count && i < channel_names_.size(); ++i)
    writer_.PushTemperature(t, channel_names_[i], r.temp_c[i], r.temp_c[i], ChannelHealthName(r.health[i]));
  for (std::size_t i = 0; i < r.axis_count && i < axis_names_.size(); ++i) {
    const AxisRecord& a = r.axes[i];
    writer_.PushCompensation(t, axis_names_[i], a.cnc_position_mm, a.output_um,
                             runtime::AxisCompensationState(r.link_read_ok, a.enabled, a.thermal_used, a.fallback_model));
  }
  // Raised and cleared, each with the axes it was raised or cleared on ("no_model_for_axis(Y)").
  std::uint32_t raised = r.alarms & ~last_alarms_;
  std::uint32_t cleared = last_alarms_ & ~r.alarms;
  std::array<std::uint32_t, runtime::kRecordMaxAxes> axis_raised{}, axis_cleared{};
  for (std::size_t i = 0; i < r.axis_count; ++i) {
    axis_raised[i] = r.axes[i].alarms & ~last_axis_alarms_[i];
    axis_cleared[i] = last_axis_alarms_[i] & ~r.axes[i].alarms;
    raised |= axis_raised[i];
    cleared |= axis_cleared[i];
    last_axis_alarms_[i] = r.axes[i].alarms;
  }
  const std::size_t n = r.axis_count;
  if (raised)
    writer_.PushAlarm(t, "warning", alarm_source_,
                      "raised: " + runtime::AlarmNamesWithAxes(raised, std::span(axis_raised.data(), n), axis_names_));
  if (cleared)
    writer_.PushAlarm(t, "info", alarm_source_,
                      "cleared: " + runtime::AlarmNamesWithAxes(cleared, std::span(axis_cleared.data(), n), axis_names_));
  last_alarms_ = r.alarms;
  ++records_;
}

void HistoryLogger::LogModelChange(double time_s, const std::string& sha256, const std::string& revision,
                                   const std::string& note) {
  writer_.PushModelChange(time_s + offset_s_, sha256, revision, note);
}

}  // namespace trueaxis::station
