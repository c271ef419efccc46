#pragma once
// AlarmBook: the alarm list of the web front end for any number of machines. Each machine
// reports the names of its active alarms; a name newly active opens an entry, a name no longer
// active closes it (kept, inactive, until `capacity` older entries push it out). An entry is
// acknowledged once, by a named user. Thread-safe.
#include <cstdint>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

class AlarmBook {
 public:
  explicit AlarmBook(std::size_t capacity = 10000) : capacity_(capacity) {}
  // `messages[name]` describes an alarm (optional).
  void Update(const std::string& machine_id, const std::vector<std::string>& active_names, double unix_s,
              const std::map<std::string, std::string>& messages = {});
  // Throws BackendError 404 (unknown id) or 409 (acknowledged already).
  void Acknowledge(const std::string& id, const std::string& user, double unix_s);
  std::vector<AlarmEntry> Newest(std::size_t limit) const;  // active first, then newest first

 private:
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::uint64_t next_ = 1;
  std::map<std::uint64_t, AlarmEntry> entries_;                                        // by number
  std::unordered_map<std::string, std::map<std::string, std::uint64_t>> active_;       // machine → name → number
  std::unordered_map<std::string, std::uint64_t> by_id_;
};

}  // namespace trueaxis::web
