#pragma once
// HistoryLogger: turns the CycleRecords the loop hands over (CycleRecorder)
// into history-database entries (store::HistoryWriter): every channel's value
// and health, every axis's position and correction, each alarm raised or
// cleared, and model changes. Runs on a non-real-time thread (it allocates
// strings); the writer's own thread does the disk work.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::station {

using runtime::AlarmNames;
using runtime::AxisRecord;
using runtime::ChannelHealth;
using runtime::CycleRecord;

class HistoryLogger {
 public:
  // `time_offset_s` is added to the loop's time (e.g. the Unix time the loop started).
  // `alarm_source` names who raised the alarms (the workshop server: the machine's name).
  HistoryLogger(store::HistoryWriter& writer, std::vector<std::string> axis_names,
                std::vector<std::string> channel_names, double time_offset_s = 0,
                std::string alarm_source = "compensator");
  void Log(const CycleRecord& record);
  // A model was published (label, revision, sha).
  void LogModelChange(double time_s, const std::string& sha256, const std::string& revision, const std::string& note);
  std::uint64_t records() const { return records_; }

 private:
  store::HistoryWriter& writer_;
  std::vector<std::string> axis_names_, channel_names_;
  double offset_s_;
  std::string alarm_source_;
  std::uint32_t last_alarms_ = 0;
  std::array<std::uint32_t, runtime::kRecordMaxAxes> last_axis_alarms_{};
  std::uint64_t records_ = 0;
};

const char* ChannelHealthName(ChannelHealth h);

}  // namespace trueaxis::station
