#include "trueaxis/store/history_record.hpp"

#include <cstring>

namespace trueaxis::store {

void CopyTruncated(char* dst, std::size_t capacity, std::string_view src) noexcept {
  if (capacity == 0) return;
  std::size_t n = std::min(src.size(), capacity - 1);
  // Do not cut a UTF-8 sequence in half: back up over continuation bytes.
  if (n < src.size())
    while (n > 0 && (static_cast<unsigned char>(src[n]) & 0xC0) == 0x80) --n;
  std::memcpy(dst, src.data(), n);
  dst[n] = '\0';
}

HistoryRecord HistoryRecord::Temperature(double time_s, std::string_view channel, double raw_c, double filtered_c,
                                         std::string_view status) noexcept {
  HistoryRecord r;
  r.kind = RecordKind::kTemperature;
  r.time_s = time_s;
  r.a = raw_c;
  r.b = filtered_c;
  CopyTruncated(r.name, channel);
  CopyTruncated(r.word, status);
  return r;
}

HistoryRecord HistoryRecord::Compensation(double time_s, std::string_view axis, double position_mm,
                                          double correction_um, std::string_view state) noexcept {
  HistoryRecord r;
  r.kind = RecordKind::kCompensation;
  r.time_s = time_s;
  r.a = position_mm;
  r.b = correction_um;
  CopyTruncated(r.name, axis);
  CopyTruncated(r.word, state);
  return r;
}

HistoryRecord HistoryRecord::Alarm(double time_s, std::string_view severity, std::string_view source,
                                   std::string_view message) noexcept {
  HistoryRecord r;
  r.kind = RecordKind::kAlarm;
  r.time_s = time_s;
  CopyTruncated(r.name, source);
  CopyTruncated(r.word, severity);
  CopyTruncated(r.text, message);
  return r;
}

HistoryRecord HistoryRecord::ModelChange(double time_s, std::string_view sha256, std::string_view revision,
                                         std::string_view note) noexcept {
  HistoryRecord r;
  r.kind = RecordKind::kModelChange;
  r.time_s = time_s;
  CopyTruncated(r.name, revision);
  CopyTruncated(r.word, sha256);
  CopyTruncated(r.text, note);
  return r;
}

}  // namespace trueaxis::store
