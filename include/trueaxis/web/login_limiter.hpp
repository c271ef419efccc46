#pragma once
// LoginLimiter: login rate limiting and temporary lockout. Failed logins are counted per user
// name and per client address within `window_s`; at `max_failures` that name (or address) is
// locked for `lockout_s` — even the right password is refused then, so guessing gains nothing.
// A successful login clears the name's count. Thread-safe; memory bounded by `max_entries`.
#include <mutex>
#include <string>
#include <unordered_map>

namespace trueaxis::web {

struct LoginLimits {
  int max_failures = 5;
  double window_s = 15 * 60;
  double lockout_s = 5 * 60;
  int max_failures_per_address = 20;  // several names tried from one address
  std::size_t max_entries = 100000;
};

class LoginLimiter {
 public:
  explicit LoginLimiter(LoginLimits limits = {}) : limits_(limits) {}
  const LoginLimits& limits() const { return limits_; }
  // Seconds until the user or address may try again (0: now).
  double LockedForS(const std::string& user, const std::string& address, double now_s) const;
  void RecordFailure(const std::string& user, const std::string& address, double now_s);
  void RecordSuccess(const std::string& user);

 private:
  struct Counter {
    int failures = 0;
    double window_start_s = 0;
    double locked_until_s = 0;
  };
  void Count(std::unordered_map<std::string, Counter>& map, const std::string& key, int max, double now_s);
  LoginLimits limits_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Counter> by_user_, by_address_;
};

}  // namespace trueaxis::web
