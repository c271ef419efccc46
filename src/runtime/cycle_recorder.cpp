#include "trueaxis/runtime/cycle_recorder.hpp"

#include <algorithm>

namespace trueaxis::runtime {

void FillRecord(const CycleStatus& s, CycleRecord& r) {
  r.cycle = s.cycle;
  r.time_s = s.time_s;
  r.alarms = s.alarms;
  r.model_id = s.model_id;
  r.link_read_ok = s.link_read_ok;
  r.write_ok = s.write_ok;
  r.temperatures_ok = s.temperatures_ok;
  r.coolant = s.coolant;
  r.axis_count = static_cast<std::uint8_t>(std::min(s.axes.size(), kRecordMaxAxes));
  r.channel_count = static_cast<std::uint8_t>(std::min(s.channels.size(), kRecordMaxChannels));
  for (std::size_t i = 0; i < r.axis_count; ++i) {
    const AxisStatus& a = s.axes[i];
    AxisRecord& o = r.axes[i];
    o.cnc_position_mm = a.cnc_position_mm;
    o.direction = static_cast<std::int8_t>(DirectionSign(a.direction));
    o.enabled = a.enabled;
    o.thermal_used = a.thermal_used;
    o.fallback_model = static_cast<std::int8_t>(a.fallback_model);
    o.geometric_um = a.prediction.geometric_um;
    o.thermal_um = a.prediction.thermal_um;
    o.ambient_um = a.prediction.ambient_um;
    o.desired_um = a.desired_um;
    o.output_um = a.output_um;
    o.written_um = a.written_um;
    o.alarms = a.alarms;
  }
  for (std::size_t i = 0; i < r.channel_count; ++i) {
    r.temp_c[i] = s.channels[i].value_c;
    r.health[i] = s.channels[i].health;
  }
}

std::string RecordAlarmNames(const CycleRecord& r, std::span<const std::string> axis_names) {
  std::array<std::uint32_t, kRecordMaxAxes> axis_alarms{};
  for (std::size_t i = 0; i < r.axis_count; ++i) axis_alarms[i] = r.axes[i].alarms;
  return AlarmNamesWithAxes(r.alarms, std::span<const std::uint32_t>(axis_alarms.data(), r.axis_count), axis_names);
}

void CycleRecorder::OnCycle(const CycleStatus& status) {
  bool alarm_edge = first_ || status.alarms != last_alarms_;
  for (std::size_t i = 0; i < status.axes.size() && i < kRecordMaxAxes; ++i) {
    alarm_edge = alarm_edge || status.axes[i].alarms != last_axis_alarms_[i];
    last_axis_alarms_[i] = status.axes[i].alarms;
  }
  first_ = false;
  last_alarms_ = status.alarms;
  if (!alarm_edge && status.cycle % every_ != 0) return;
  FillRecord(status, scratch_);
  if (!ring_.TryPush(scratch_)) dropped_.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace trueaxis::runtime
