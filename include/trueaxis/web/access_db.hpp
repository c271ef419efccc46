#pragma once
// AccessDb: the SQLite file of the web front end's users and its audit log (docs/web.md).
//
//   users(name PRIMARY KEY, role, password_hash, created_utc)   — argon2id hashes only
//   audit(id, time_utc, unix_s, user, role, remote, action, target, detail, outcome)
//
// One connection guarded by a mutex: any HTTP worker may call it. A file that is not an access
// database (another program's SQLite, not SQLite at all) is refused with an InputError naming it.
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/web/password_hash.hpp"
#include "trueaxis/web/role.hpp"

struct sqlite3;

namespace trueaxis::web {

struct UserRecord {
  std::string name;
  Role role = Role::kViewer;
  std::string password_hash;
  std::string created_utc;
};

struct AuditEntry {
  std::int64_t id = 0;
  std::string time_utc;
  double unix_s = 0;
  std::string user;       // "" before login (a failed login names the attempted user in `target`)
  std::string role;
  std::string remote;     // client address:port
  std::string action;     // "login", "logout", "axis_enable", "alarm_ack", ...
  std::string target;     // machine / axis / alarm / user concerned
  std::string detail;
  std::string outcome;    // "ok", "refused: ...", "failed: ..."
};

class AccessDb {
 public:
  static constexpr std::int32_t kApplicationId = 0x54415755;  // "TAWU"
  explicit AccessDb(const std::string& path);  // creates a missing file
  ~AccessDb();
  AccessDb(const AccessDb&) = delete;
  AccessDb& operator=(const AccessDb&) = delete;
  const std::string& path() const { return path_; }

  // Names: 1–64 characters of [A-Za-z0-9_.@-]; passwords: at least 8 characters. InputError otherwise,
  // or when the user exists.
  void AddUser(const std::string& name, Role role, const std::string& password, HashCost cost = HashCost::kInteractive);
  void SetPassword(const std::string& name, const std::string& password, HashCost cost = HashCost::kInteractive);
  bool RemoveUser(const std::string& name);
  std::optional<UserRecord> FindUser(const std::string& name) const;
  std::vector<UserRecord> Users() const;

  std::int64_t Record(const AuditEntry& entry);  // id and time are set here; returns the id
  void SetDetail(std::int64_t id, const std::string& detail);  // of a row already written
  std::vector<AuditEntry> RecentAudit(std::size_t limit) const;  // newest first

 private:
  void Exec(const char* sql) const;
  std::string path_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
};

void CheckUserName(const std::string& name);
void CheckPassword(const std::string& password);

}  // namespace trueaxis::web
