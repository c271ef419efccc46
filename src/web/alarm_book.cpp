#include "trueaxis/web/alarm_book.hpp"

#include <algorithm>

namespace trueaxis::web {

void AlarmBook::Update(const std::string& machine_id, const std::vector<std::string>& active_names, double unix_s,
                       const std::map<std::string, std::string>& messages) {
  std::lock_guard lock(mutex_);
  auto& open = active_[machine_id];
  const std::set<std::string> now(active_names.begin(), active_names.end());
  for (auto it = open.begin(); it != open.end();) {
    if (now.count(it->first)) {
      ++it;
      continue;
    }
    if (auto e = entries_.find(it->second); e != entries_.end()) e->second.active = false;
    it = open.erase(it);
  }
  for (const auto& name : now) {
    if (open.count(name)) continue;
    const std::uint64_t n = next_++;
    AlarmEntry e;
    e.id = machine_id + ":" + std::to_string(n);
    e.machine_id = machine_id;
    e.name = name;
    if (auto m = messages.find(name); m != messages.end()) e.message = m->second;
    e.raised_unix_s = unix_s;
    by_id_[e.id] = n;
    entries_[n] = std::move(e);
    open[name] = n;
  }
  // Forget the oldest inactive entries beyond the capacity (active ones are always kept).
  for (auto it = entries_.begin(); entries_.size() > capacity_ && it != entries_.end();) {
    if (it->second.active) {
      ++it;
      continue;
    }
    by_id_.erase(it->second.id);
    it = entries_.erase(it);
  }
}

void AlarmBook::Acknowledge(const std::string& id, const std::string& user, double unix_s) {
  std::lock_guard lock(mutex_);
  auto n = by_id_.find(id);
  if (n == by_id_.end()) throw BackendError(404, "no alarm '" + id + "'");
  AlarmEntry& e = entries_.at(n->second);
  if (e.acknowledged) throw BackendError(409, "alarm '" + id + "' was acknowledged already by " + e.acknowledged_by);
  e.acknowledged = true;
  e.acknowledged_by = user;
  e.acknowledged_unix_s = unix_s;
}

std::vector<AlarmEntry> AlarmBook::Newest(std::size_t limit) const {
  std::lock_guard lock(mutex_);
  std::vector<AlarmEntry> out;
  for (auto it = entries_.rbegin(); it != entries_.rend(); ++it)
    if (it->second.active) out.push_back(it->second);
  for (auto it = entries_.rbegin(); it != entries_.rend() && out.size() < limit; ++it)
    if (!it->second.active) out.push_back(it->second);
  if (out.size() > limit) out.resize(limit);
  return out;
}

}  // namespace trueaxis::web
