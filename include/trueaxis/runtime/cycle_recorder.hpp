#pragma once
// CycleRecorder: a CycleObserver that copies decimated cycle snapshots into a
// preallocated SpscRing for a non-real-time consumer (history store, CSV log,
// demo plots). Real-time safe: fixed-size records, no allocation, no lock.
//
// Every `every_n_cycles`-th cycle is recorded, and every cycle whose alarm
// bits differ from the previous cycle's, so a consumer sees each alarm being
// raised and cleared (unless the ring overflows: see Dropped()).
#include <array>
#include <atomic>
#include <cstdint>
#include <span>
#include <string>

#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/runtime/spsc_ring.hpp"

namespace trueaxis::runtime {

inline constexpr std::size_t kRecordMaxAxes = 8;
inline constexpr std::size_t kRecordMaxChannels = 32;

struct AxisRecord {
  double cnc_position_mm = 0;
  std::int8_t direction = 1;  // +1 forward model, −1 reverse model
  bool enabled = false;
  bool thermal_used = false;
  std::int8_t fallback_model = -1;  // AxisStatus::fallback_model
  double geometric_um = 0, thermal_um = 0, ambient_um = 0;  // predicted error parts
  double desired_um = 0;   // target correction (NaN = hold)
  double output_um = 0;    // shaped correction, physical
  double written_um = 0;   // written, CNC units
  std::uint32_t alarms = 0;  // AxisStatus::alarms: the alarm bits this axis raised
};

struct CycleRecord {
  std::uint64_t cycle = 0;
  double time_s = 0;
  std::uint32_t alarms = 0;
  std::uint64_t model_id = 0;
  bool link_read_ok = false, write_ok = false, temperatures_ok = false;
  CoolantState coolant = CoolantState::kOff;
  std::uint8_t axis_count = 0, channel_count = 0;
  std::array<AxisRecord, kRecordMaxAxes> axes{};
  std::array<double, kRecordMaxChannels> temp_c{};          // value used (NaN when lost)
  std::array<ChannelHealth, kRecordMaxChannels> health{};
};

void FillRecord(const CycleStatus& status, CycleRecord& out);
// The record's alarms as a user reads them, with the axes behind each (AlarmNamesWithAxes):
// "no_model_for_axis(Y)|link_read"; "" when none. Not for the RT thread.
std::string RecordAlarmNames(const CycleRecord& record, std::span<const std::string> axis_names);

class CycleRecorder : public CycleObserver {
 public:
  CycleRecorder(std::size_t capacity, std::uint64_t every_n_cycles) : ring_(capacity), every_(every_n_cycles ? every_n_cycles : 1) {}
  void OnCycle(const CycleStatus& status) override;
  bool Pop(CycleRecord& out) { return ring_.TryPop(out); }
  std::uint64_t Dropped() const { return dropped_.load(); }

 private:
  SpscRing<CycleRecord> ring_;
  std::uint64_t every_;
  std::uint32_t last_alarms_ = 0;
  std::array<std::uint32_t, kRecordMaxAxes> last_axis_alarms_{};  // an alarm moving to another axis is an edge too
  bool first_ = true;
  CycleRecord scratch_;
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace trueaxis::runtime
