#include "trueaxis/demo/alarm_tally.hpp"

#include "trueaxis/runtime/cycle_step.hpp"

namespace trueaxis::demo {

void AlarmTally::Update(std::uint32_t alarms, double time_s) {
  if (alarms == active_) return;
  for (int b = 0; b < kBits; ++b) {
    const std::uint32_t bit = 1u << b;
    const bool was = active_ & bit, now = alarms & bit;
    if (now && !was) {
      if (times_[b]++ == 0) first_s_[b] = time_s;
      last_s_[b] = since_s_[b] = time_s;
    } else if (was && !now) {
      total_s_[b] += time_s - since_s_[b];
      cleared_s_[b] = time_s;
    }
  }
  active_ = alarms;
}

void AlarmTally::Pause(double time_s) { Update(0, time_s); }

std::vector<AlarmSummaryRow> AlarmTally::Rows(double end_s) const {
  std::vector<AlarmSummaryRow> rows;
  for (int b = 0; b < kBits; ++b) {
    if (times_[b] == 0) continue;
    AlarmSummaryRow r;
    r.alarm = runtime::AlarmNames(1u << b);
    if (r.alarm.empty()) r.alarm = "alarm bit " + std::to_string(b);
    r.times = times_[b];
    r.total_s = total_s_[b];
    r.first_raised_s = first_s_[b];
    r.last_raised_s = last_s_[b];
    if (active_ & (1u << b)) r.total_s += end_s - since_s_[b];
    else r.last_cleared_s = cleared_s_[b];
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace trueaxis::demo
