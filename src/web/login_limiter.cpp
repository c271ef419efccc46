#include "trueaxis/web/login_limiter.hpp"

#include <algorithm>

namespace trueaxis::web {

double LoginLimiter::LockedForS(const std::string& user, const std::string& address, double now_s) const {
  std::lock_guard lock(mutex_);
  double wait = 0;
  if (auto it = by_user_.find(user); it != by_user_.end()) wait = std::max(wait, it->second.locked_until_s - now_s);
  if (auto it = by_address_.find(address); it != by_address_.end())
    wait = std::max(wait, it->second.locked_until_s - now_s);
  return wait;
}

void LoginLimiter::Count(std::unordered_map<std::string, Counter>& map, const std::string& key, int max, double now_s) {
  if (map.size() >= limits_.max_entries && !map.count(key)) {  // drop counters whose window and lock are over
    for (auto it = map.begin(); it != map.end();)
      it = (now_s - it->second.window_start_s > limits_.window_s && now_s > it->second.locked_until_s) ? map.erase(it)
                                                                                                       : std::next(it);
    if (map.size() >= limits_.max_entries) map.erase(map.begin());
  }
  Counter& c = map[key];
  if (now_s - c.window_start_s > limits_.window_s) c = Counter{0, now_s, c.locked_until_s};
  if (++c.failures >= max) {
    c.locked_until_s = now_s + limits_.lockout_s;
    c.failures = 0;
    c.window_start_s = now_s;
  }
}

void LoginLimiter::RecordFailure(const std::string& user, const std::string& address, double now_s) {
  std::lock_guard lock(mutex_);
  Count(by_user_, user, limits_.max_failures, now_s);
  Count(by_address_, address, limits_.max_failures_per_address, now_s);
}

void LoginLimiter::RecordSuccess(const std::string& user) {
  std::lock_guard lock(mutex_);
  by_user_.erase(user);
}

}  // namespace trueaxis::web
