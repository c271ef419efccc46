#include "trueaxis/web/login_limiter.hpp"

#include <algorithm>
#include <utility>

namespace trueaxis::web {

LoginLimiter::Attempt::Attempt(LoginLimiter* owner, std::string user, std::string address, double now_s, Verdict v,
                               double retry_after_s, bool by_address)
    : owner_(v == Verdict::kGranted ? owner : nullptr), user_(std::move(user)), address_(std::move(address)), verdict_(v),
      retry_after_s_(retry_after_s), by_address_(by_address), reserved_s_(now_s) {}

LoginLimiter::Attempt::Attempt(Attempt&& other) noexcept
    : owner_(std::exchange(other.owner_, nullptr)), user_(std::move(other.user_)), address_(std::move(other.address_)),
      verdict_(other.verdict_), retry_after_s_(other.retry_after_s_), by_address_(other.by_address_),
      reserved_s_(other.reserved_s_) {}

LoginLimiter::Attempt::~Attempt() {
  // Dropped unfinished (an exception while checking): counted as failed, never as a free guess.
  if (owner_) owner_->Finish(user_, address_, false, reserved_s_);
}

void LoginLimiter::Attempt::Succeeded() {
  if (auto* o = std::exchange(owner_, nullptr)) o->Finish(user_, address_, true, reserved_s_);
}

void LoginLimiter::Attempt::Failed(double now_s) {
  if (auto* o = std::exchange(owner_, nullptr)) o->Finish(user_, address_, false, now_s);
}

LoginLimiter::Counter& LoginLimiter::Entry(Map& map, const std::string& key, double now_s) {
  if (map.size() >= limits_.max_entries && !map.count(key)) {  // drop counters whose window and lock are over
    for (auto it = map.begin(); it != map.end();)
      it = (now_s - it->second.window_start_s > limits_.window_s && now_s > it->second.locked_until_s &&
            it->second.in_flight == 0)
               ? map.erase(it)
               : std::next(it);
    if (map.size() >= limits_.max_entries) {  // still full: drop one not being checked
      auto idle = std::find_if(map.begin(), map.end(), [](const auto& e) { return e.second.in_flight == 0; });
      if (idle != map.end()) map.erase(idle);
    }
  }
  Counter& c = map[key];
  if (now_s - c.window_start_s > limits_.window_s) {
    c.failures = 0;
    c.window_start_s = now_s;
  }
  return c;
}

LoginLimiter::Attempt LoginLimiter::Reserve(const std::string& user, const std::string& address, double now_s) {
  std::lock_guard lock(mutex_);
  Counter& u = Entry(by_user_, user, now_s);
  Counter& a = Entry(by_address_, address, now_s);
  const double user_wait = u.locked_until_s - now_s, address_wait = a.locked_until_s - now_s;
  if (user_wait > 0 || address_wait > 0)
    return Attempt(this, user, address, now_s, Verdict::kLocked, std::max(user_wait, address_wait), user_wait <= 0);
  // The attempts still being checked count as failures already: parallel guesses cannot pass the
  // limit while the first ones hash. They end within a second or so: try again then.
  const bool user_full = u.failures + u.in_flight >= limits_.max_failures;
  if (user_full || a.failures + a.in_flight >= limits_.max_failures_per_address)
    return Attempt(this, user, address, now_s, Verdict::kPending, 1, !user_full);
  if (hashes_in_flight_ >= limits_.max_hashes_in_flight) return Attempt(this, user, address, now_s, Verdict::kBusy, 1);
  ++u.in_flight;
  ++a.in_flight;
  ++hashes_in_flight_;
  return Attempt(this, user, address, now_s);
}

void LoginLimiter::CountFailure(Map& map, const std::string& key, int max, double now_s) {
  Counter& c = Entry(map, key, now_s);
  if (++c.failures >= max) {
    c.locked_until_s = now_s + limits_.lockout_s;
    c.failures = 0;
    c.window_start_s = now_s;
  }
}

void LoginLimiter::Finish(const std::string& user, const std::string& address, bool ok, double now_s) {
  std::lock_guard lock(mutex_);
  hashes_in_flight_ = std::max(0, hashes_in_flight_ - 1);
  for (auto* map : {&by_user_, &by_address_})
    if (auto it = map->find(map == &by_user_ ? user : address); it != map->end())
      it->second.in_flight = std::max(0, it->second.in_flight - 1);
  if (ok) {
    if (auto it = by_user_.find(user); it != by_user_.end()) {
      if (it->second.in_flight == 0) by_user_.erase(it);
      else it->second = Counter{0, now_s, 0, it->second.in_flight};
    }
    return;
  }
  CountFailure(by_user_, user, limits_.max_failures, now_s);
  CountFailure(by_address_, address, limits_.max_failures_per_address, now_s);
}

double LoginLimiter::LockedForS(const std::string& user, const std::string& address, double now_s) const {
  std::lock_guard lock(mutex_);
  double wait = 0;
  if (auto it = by_user_.find(user); it != by_user_.end()) wait = std::max(wait, it->second.locked_until_s - now_s);
  if (auto it = by_address_.find(address); it != by_address_.end())
    wait = std::max(wait, it->second.locked_until_s - now_s);
  return wait;
}

int LoginLimiter::hashes_in_flight() const {
  std::lock_guard lock(mutex_);
  return hashes_in_flight_;
}

}  // namespace trueaxis::web
