#include "trueaxis/web/session_store.hpp"

#include "trueaxis/web/password_hash.hpp"

namespace trueaxis::web {

bool SessionStore::Expired(const Session& s, double now_s) const {
  return now_s - s.last_seen_s > timeouts_.idle_timeout_s || now_s - s.created_s > timeouts_.absolute_timeout_s;
}

Session SessionStore::Create(const std::string& user, Role role, const std::string& password_hash, double now_s) {
  Session s{RandomToken(), RandomToken(), user, role, password_hash, now_s, now_s};
  std::lock_guard lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();)  // sweep the expired ones
    it = Expired(it->second, now_s) ? sessions_.erase(it) : std::next(it);
  while (sessions_.size() >= timeouts_.max_sessions) {
    auto oldest = sessions_.begin();
    for (auto it = sessions_.begin(); it != sessions_.end(); ++it)
      if (it->second.created_s < oldest->second.created_s) oldest = it;
    sessions_.erase(oldest);
  }
  sessions_[s.id] = s;
  return s;
}

std::optional<Session> SessionStore::Touch(const std::string& id, double now_s) {
  std::lock_guard lock(mutex_);
  auto it = sessions_.find(id);
  if (it == sessions_.end()) return std::nullopt;
  if (Expired(it->second, now_s)) {
    sessions_.erase(it);
    return std::nullopt;
  }
  it->second.last_seen_s = now_s;
  return it->second;
}

void SessionStore::Remove(const std::string& id) {
  std::lock_guard lock(mutex_);
  sessions_.erase(id);
}

void SessionStore::RemoveUser(const std::string& user) {
  std::lock_guard lock(mutex_);
  for (auto it = sessions_.begin(); it != sessions_.end();) it = it->second.user == user ? sessions_.erase(it) : std::next(it);
}

std::size_t SessionStore::Count() const {
  std::lock_guard lock(mutex_);
  return sessions_.size();
}

}  // namespace trueaxis::web
