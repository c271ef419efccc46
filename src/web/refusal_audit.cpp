#include "trueaxis/web/refusal_audit.hpp"

#include <fmt/format.h>

#include "trueaxis/store/time_text.hpp"

namespace trueaxis::web {

RefusalAudit::~RefusalAudit() {
  try {
    Flush();
  } catch (const std::exception&) {
  }
}

void RefusalAudit::Write(Burst& b) {
  if (b.written == b.count) return;
  db_.SetDetail(b.row, fmt::format("{} attempt{} refused from {} to {}", b.count, b.count == 1 ? "" : "s",
                                   store::FormatUtc(b.first_s), store::FormatUtc(b.last_s)));
  b.written = b.count;
  b.written_s = b.last_s;
}

void RefusalAudit::Refused(const std::string& key, const AuditEntry& entry, double unix_s) {
  std::lock_guard lock(mutex_);
  auto it = bursts_.find(key);
  if (it != bursts_.end() && unix_s - it->second.last_s <= limits_.burst_gap_s) {
    Burst& b = it->second;
    ++b.count;
    b.last_s = unix_s;
    if (unix_s - b.written_s >= limits_.rewrite_interval_s) Write(b);
    return;
  }
  if (it != bursts_.end()) {  // that key's previous burst is over: its last count, then a new row
    Write(it->second);
    bursts_.erase(it);
  }
  if (bursts_.size() >= limits_.max_bursts) {  // full: write out and forget the bursts that are over
    for (auto b = bursts_.begin(); b != bursts_.end();) {
      if (unix_s - b->second.last_s > limits_.burst_gap_s || bursts_.size() >= limits_.max_bursts) {
        Write(b->second);
        b = bursts_.erase(b);
      } else {
        ++b;
      }
    }
  }
  Burst b;
  AuditEntry first = entry;
  first.detail = fmt::format("1 attempt refused at {}", store::FormatUtc(unix_s));
  b.row = db_.Record(first);
  b.count = b.written = 1;
  b.first_s = b.last_s = b.written_s = unix_s;
  bursts_.emplace(key, b);
}

void RefusalAudit::Flush() {
  std::lock_guard lock(mutex_);
  for (auto& [key, b] : bursts_) Write(b);
}

}  // namespace trueaxis::web
