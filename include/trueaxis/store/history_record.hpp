#pragma once
// HistoryRecord: one entry for the history database, fixed size and
// trivially copyable, so a real-time producer can hand it to the writer
// queue without allocating. Text fields are truncated to their buffers
// (names and status words are short; alarm messages are cut at 159 bytes).
#include <cstdint>
#include <string_view>

namespace trueaxis::store {

enum class RecordKind : std::uint8_t { kTemperature, kCompensation, kAlarm, kModelChange };

struct HistoryRecord {
  RecordKind kind = RecordKind::kTemperature;
  double time_s = 0;  // seconds since the Unix epoch, UTC (or a simulation clock)
  // kTemperature: a = raw_c, b = filtered_c;          name = channel, word = status
  // kCompensation: a = position_mm, b = correction_um; name = axis,    word = state
  // kAlarm:                                             name = source,  word = severity, text = message
  // kModelChange:                                       name = revision, word = sha256, text = note
  double a = 0;
  double b = 0;
  char name[48] = {};
  char word[72] = {};
  char text[160] = {};

  static HistoryRecord Temperature(double time_s, std::string_view channel, double raw_c, double filtered_c,
                                   std::string_view status) noexcept;
  static HistoryRecord Compensation(double time_s, std::string_view axis, double position_mm, double correction_um,
                                    std::string_view state) noexcept;
  static HistoryRecord Alarm(double time_s, std::string_view severity, std::string_view source,
                             std::string_view message) noexcept;
  static HistoryRecord ModelChange(double time_s, std::string_view sha256, std::string_view revision,
                                   std::string_view note) noexcept;
};

// Copies at most N-1 bytes and terminates; never splits a UTF-8 sequence.
void CopyTruncated(char* dst, std::size_t capacity, std::string_view src) noexcept;
template <std::size_t N>
void CopyTruncated(char (&dst)[N], std::string_view src) noexcept {
  CopyTruncated(dst, N, src);
}

}  // namespace trueaxis::store
