#pragma once
// SessionStore: the logged-in sessions of the web front end, in memory (a restart logs everyone
// out). A session id is 32 random bytes (hex) sent only in an HttpOnly, SameSite=Strict cookie;
// each session has its own CSRF token that every state-changing request must echo in the
// X-CSRF-Token header. A session ends on logout, after `idle_timeout_s` without a request, or
// `absolute_timeout_s` after login, whichever comes first. Thread-safe.
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>

#include "trueaxis/web/role.hpp"

namespace trueaxis::web {

struct SessionTimeouts {
  double idle_timeout_s = 15 * 60;
  double absolute_timeout_s = 8 * 3600;
  std::size_t max_sessions = 10000;  // oldest dropped beyond this (memory bound)
};

struct Session {
  std::string id;
  std::string csrf_token;
  std::string user;
  Role role = Role::kViewer;
  std::string password_hash;  // the user's at login: a changed password ends the session
  double created_s = 0;    // on the store's clock (steady seconds)
  double last_seen_s = 0;
};

class SessionStore {
 public:
  explicit SessionStore(SessionTimeouts timeouts = {}) : timeouts_(timeouts) {}
  const SessionTimeouts& timeouts() const { return timeouts_; }

  Session Create(const std::string& user, Role role, const std::string& password_hash, double now_s);
  // The live session with this id, its idle clock restarted; nullopt when unknown or expired
  // (an expired one is removed).
  std::optional<Session> Touch(const std::string& id, double now_s);
  void Remove(const std::string& id);
  // Ends every session of a user (removed user, changed password).
  void RemoveUser(const std::string& user);
  std::size_t Count() const;

 private:
  bool Expired(const Session& s, double now_s) const;
  SessionTimeouts timeouts_;
  mutable std::mutex mutex_;
  std::unordered_map<std::string, Session> sessions_;
};

}  // namespace trueaxis::web
