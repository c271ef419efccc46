#pragma once
// RefusalAudit: refused login attempts (a locked-out name or address, the server busy with other
// password checks) go to the audit log as one row per burst with a count, not one row per request:
// a client hammering a locked name cannot grow the log (or its disk writes) with its request rate.
//
// A burst is the refusals of one key (e.g. "locked user op") with less than `burst_gap_s` between
// them. Its first refusal writes the row; later ones count in memory and rewrite the row's detail
// ("N attempts refused from … to …") at most every `rewrite_interval_s`; the last count is written
// when the next burst of that key starts, when the table is full, or at Flush() (the server's stop).
// Thread-safe; at most `max_bursts` bursts are remembered.
#include <cstdint>
#include <mutex>
#include <string>
#include <unordered_map>

#include "trueaxis/web/access_db.hpp"

namespace trueaxis::web {

struct RefusalAuditLimits {
  double burst_gap_s = 60;
  double rewrite_interval_s = 1;
  std::size_t max_bursts = 10000;
};

class RefusalAudit {
 public:
  explicit RefusalAudit(AccessDb& db, RefusalAuditLimits limits = {}) : db_(db), limits_(limits) {}
  ~RefusalAudit();  // Flush(), errors ignored
  // `entry` describes the refusal (action, target, remote, outcome); `unix_s` is wall-clock time.
  void Refused(const std::string& key, const AuditEntry& entry, double unix_s);
  void Flush();

 private:
  struct Burst {
    std::int64_t row = 0;
    long count = 0, written = 0;
    double first_s = 0, last_s = 0, written_s = 0;
  };
  void Write(Burst& b);  // the mutex is held
  AccessDb& db_;
  RefusalAuditLimits limits_;
  std::mutex mutex_;
  std::unordered_map<std::string, Burst> bursts_;
};

}  // namespace trueaxis::web
