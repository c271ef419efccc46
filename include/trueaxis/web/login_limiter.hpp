#pragma once
// LoginLimiter: login rate limiting and temporary lockout. Failed logins are counted per user
// name and per client address within `window_s`; at `max_failures` that name (or address) is
// locked for `lockout_s` — even the right password is refused then, so guessing gains nothing.
// A successful login clears the name's count.
//
// An attempt is reserved before its password is hashed (Reserve), atomically for the name and the
// address: attempts still being checked count as failures already, so parallel guesses cannot
// pass the limit while the first ones are hashing — at most `max_failures` guesses of a name are
// ever checked per lockout, however many arrive at once. The number of password hashes running at
// the same time is bounded too (`max_hashes_in_flight`, 64 MiB of memory each): beyond it an attempt
// is refused at once ("busy", try again in a second) instead of queueing.
// Thread-safe; memory bounded by `max_entries`.
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
  int max_hashes_in_flight = 4;       // password checks at the same time, all users
};

class LoginLimiter {
 public:
  enum class Verdict {
    kGranted,  // check the password, then Succeeded() or Failed()
    kLocked,   // the name or the address is locked out
    kPending,  // as many attempts of the name (or address) as may still fail are being checked
    kBusy,     // max_hashes_in_flight password checks are running: try again in a moment
  };

  // One reserved attempt. Until Succeeded() or Failed(), it counts as a failure in progress; one
  // dropped without either (an exception) is counted as failed.
  class Attempt {
   public:
    Attempt(Attempt&& other) noexcept;
    Attempt& operator=(Attempt&&) = delete;
    ~Attempt();
    Verdict verdict() const { return verdict_; }
    bool granted() const { return verdict_ == Verdict::kGranted; }
    double retry_after_s() const { return retry_after_s_; }
    bool by_address() const { return by_address_; }  // kLocked/kPending: the address rather than the name
    void Succeeded();
    void Failed(double now_s);

   private:
    friend class LoginLimiter;
    Attempt(LoginLimiter* owner, std::string user, std::string address, double now_s, Verdict v = Verdict::kGranted,
            double retry_after_s = 0, bool by_address = false);
    LoginLimiter* owner_;  // null once finished (or never granted)
    std::string user_, address_;
    Verdict verdict_;
    double retry_after_s_;
    bool by_address_;
    double reserved_s_;
  };

  explicit LoginLimiter(LoginLimits limits = {}) : limits_(limits) {}
  const LoginLimits& limits() const { return limits_; }
  Attempt Reserve(const std::string& user, const std::string& address, double now_s);
  // Seconds until the user or address may try again (0: now), for attempts already finished.
  double LockedForS(const std::string& user, const std::string& address, double now_s) const;
  int hashes_in_flight() const;

 private:
  struct Counter {
    int failures = 0;
    double window_start_s = 0;
    double locked_until_s = 0;
    int in_flight = 0;  // reserved, not finished
  };
  using Map = std::unordered_map<std::string, Counter>;
  Counter& Entry(Map& map, const std::string& key, double now_s);
  void CountFailure(Map& map, const std::string& key, int max, double now_s);
  void Finish(const std::string& user, const std::string& address, bool ok, double now_s);

  LoginLimits limits_;
  mutable std::mutex mutex_;
  Map by_user_, by_address_;
  int hashes_in_flight_ = 0;
};

}  // namespace trueaxis::web
