#pragma once
// AlarmTally: the compensator's alarms over a run, summarised per alarm — how many times it was
// raised, for how long in all, when first and last — from the alarm word of each cycle. Counts
// nothing itself per cycle beyond a compare; for the demo's report (an alarm summary table instead
// of a log of timestamps).
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace trueaxis::demo {

struct AlarmSummaryRow {
  std::string alarm;            // runtime::AlarmNames of its bit
  std::uint64_t times = 0;      // how many times raised
  double total_s = 0;           // how long active in all
  double first_raised_s = std::numeric_limits<double>::quiet_NaN();
  double last_raised_s = std::numeric_limits<double>::quiet_NaN();
  double last_cleared_s = std::numeric_limits<double>::quiet_NaN();  // NaN: still active at the end
};

class AlarmTally {
 public:
  // The alarms active from `time_s` on (seconds on any one clock, e.g. Unix time).
  void Update(std::uint32_t alarms, double time_s);
  // The run stops at `time_s` (e.g. the machine switched off until another day): open episodes
  // end there, and an alarm still active when the run goes on counts as raised again.
  void Pause(double time_s);
  // One row per alarm ever raised, in bit order; episodes still open count up to `end_s`.
  std::vector<AlarmSummaryRow> Rows(double end_s) const;

 private:
  static constexpr int kBits = 32;
  std::uint32_t active_ = 0;
  std::array<std::uint64_t, kBits> times_{};
  std::array<double, kBits> total_s_{}, since_s_{}, first_s_{}, last_s_{}, cleared_s_{};
};

}  // namespace trueaxis::demo
