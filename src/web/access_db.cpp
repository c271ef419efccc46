#include "trueaxis/web/access_db.hpp"

#include <sqlite3.h>

#include <cctype>
#include <chrono>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/time_text.hpp"

namespace trueaxis::web {

namespace {

struct Statement {
  sqlite3_stmt* s = nullptr;
  Statement(sqlite3* db, const char* sql, const std::string& path) {
    if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) != SQLITE_OK)
      throw InputError(path, std::string("SQL error: ") + sqlite3_errmsg(db));
  }
  ~Statement() { sqlite3_finalize(s); }
  void Bind(int i, const std::string& v) { sqlite3_bind_text(s, i, v.c_str(), static_cast<int>(v.size()), SQLITE_TRANSIENT); }
  void Bind(int i, double v) { sqlite3_bind_double(s, i, v); }
  std::string Text(int i) const {
    const auto* p = sqlite3_column_text(s, i);
    return p ? reinterpret_cast<const char*>(p) : "";
  }
};

double NowUnixS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

UserRecord ReadUser(const Statement& st) {
  UserRecord u;
  u.name = st.Text(0);
  u.role = ParseRole(st.Text(1)).value_or(Role::kViewer);
  u.password_hash = st.Text(2);
  u.created_utc = st.Text(3);
  return u;
}

}  // namespace

void CheckUserName(const std::string& name) {
  if (name.empty() || name.size() > 64) throw InputError("user", 0, "name", "must be 1 to 64 characters");
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '@' || c == '-'))
      throw InputError("user", 0, "name", "only letters, digits and _ . @ - are allowed");
}

void CheckPassword(const std::string& password) {
  if (password.size() < 8) throw InputError("user", 0, "password", "must be at least 8 characters");
  if (password.size() > 1024) throw InputError("user", 0, "password", "must be at most 1024 characters");
}

AccessDb::AccessDb(const std::string& path) : path_(path) {
  if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_NOMUTEX, nullptr) !=
      SQLITE_OK) {
    const std::string why = db_ ? sqlite3_errmsg(db_) : "out of memory";
    sqlite3_close(db_);
    throw InputError(path, "cannot open the user database: " + why);
  }
  sqlite3_busy_timeout(db_, 5000);
  try {
    int id = 0;
    bool fresh = false;
    {
      Statement app(db_, "PRAGMA application_id", path_);
      if (sqlite3_step(app.s) != SQLITE_ROW) throw InputError(path, "not a SQLite database");
      id = sqlite3_column_int(app.s, 0);
    }
    {
      Statement count(db_, "SELECT count(*) FROM sqlite_master", path_);
      sqlite3_step(count.s);
      fresh = sqlite3_column_int(count.s, 0) == 0;
    }
    if (!fresh && id != kApplicationId)
      throw InputError(path, "not a trueaxis user database (another program's file?); name another --users file");
    if (fresh) {
      Exec("PRAGMA journal_mode=WAL");
      Exec(("PRAGMA application_id=" + std::to_string(kApplicationId)).c_str());
      Exec("CREATE TABLE users(name TEXT PRIMARY KEY, role TEXT NOT NULL, password_hash TEXT NOT NULL, "
           "created_utc TEXT NOT NULL)");
      Exec("CREATE TABLE audit(id INTEGER PRIMARY KEY, time_utc TEXT NOT NULL, unix_s REAL NOT NULL, user TEXT, "
           "role TEXT, remote TEXT, action TEXT NOT NULL, target TEXT, detail TEXT, outcome TEXT)");
    }
  } catch (...) {
    sqlite3_close(db_);
    throw;
  }
}

AccessDb::~AccessDb() { sqlite3_close(db_); }

void AccessDb::Exec(const char* sql) const {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    const std::string why = err ? err : "unknown";
    sqlite3_free(err);
    throw InputError(path_, "SQL error: " + why);
  }
}

void AccessDb::AddUser(const std::string& name, Role role, const std::string& password, HashCost cost) {
  CheckUserName(name);
  CheckPassword(password);
  const std::string hash = HashPassword(password, cost);
  std::lock_guard lock(mutex_);
  Statement st(db_, "INSERT INTO users(name, role, password_hash, created_utc) VALUES(?1, ?2, ?3, ?4)", path_);
  st.Bind(1, name);
  st.Bind(2, std::string(RoleName(role)));
  st.Bind(3, hash);
  st.Bind(4, store::FormatUtc(NowUnixS()));
  if (sqlite3_step(st.s) != SQLITE_DONE) throw InputError(path_, 0, "name", "user '" + name + "' exists already");
}

void AccessDb::SetPassword(const std::string& name, const std::string& password, HashCost cost) {
  CheckPassword(password);
  const std::string hash = HashPassword(password, cost);
  std::lock_guard lock(mutex_);
  Statement st(db_, "UPDATE users SET password_hash=?2 WHERE name=?1", path_);
  st.Bind(1, name);
  st.Bind(2, hash);
  sqlite3_step(st.s);
  if (sqlite3_changes(db_) != 1) throw InputError(path_, 0, "name", "no user '" + name + "'");
}

bool AccessDb::RemoveUser(const std::string& name) {
  std::lock_guard lock(mutex_);
  Statement st(db_, "DELETE FROM users WHERE name=?1", path_);
  st.Bind(1, name);
  sqlite3_step(st.s);
  return sqlite3_changes(db_) == 1;
}

std::optional<UserRecord> AccessDb::FindUser(const std::string& name) const {
  std::lock_guard lock(mutex_);
  Statement st(db_, "SELECT name, role, password_hash, created_utc FROM users WHERE name=?1", path_);
  st.Bind(1, name);
  if (sqlite3_step(st.s) != SQLITE_ROW) return std::nullopt;
  return ReadUser(st);
}

std::vector<UserRecord> AccessDb::Users() const {
  std::lock_guard lock(mutex_);
  Statement st(db_, "SELECT name, role, password_hash, created_utc FROM users ORDER BY name", path_);
  std::vector<UserRecord> out;
  while (sqlite3_step(st.s) == SQLITE_ROW) out.push_back(ReadUser(st));
  return out;
}

std::int64_t AccessDb::Record(const AuditEntry& e) {
  const double now = NowUnixS();
  std::lock_guard lock(mutex_);
  Statement st(db_,
               "INSERT INTO audit(time_utc, unix_s, user, role, remote, action, target, detail, outcome) "
               "VALUES(?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
               path_);
  st.Bind(1, store::FormatUtc(now));
  st.Bind(2, now);
  st.Bind(3, e.user);
  st.Bind(4, e.role);
  st.Bind(5, e.remote);
  st.Bind(6, e.action);
  st.Bind(7, e.target);
  st.Bind(8, e.detail);
  st.Bind(9, e.outcome);
  if (sqlite3_step(st.s) != SQLITE_DONE) throw InputError(path_, std::string("audit write failed: ") + sqlite3_errmsg(db_));
  return sqlite3_last_insert_rowid(db_);
}

void AccessDb::SetDetail(std::int64_t id, const std::string& detail) {
  std::lock_guard lock(mutex_);
  Statement st(db_, "UPDATE audit SET detail = ?1 WHERE id = ?2", path_);
  st.Bind(1, detail);
  sqlite3_bind_int64(st.s, 2, static_cast<sqlite3_int64>(id));
  if (sqlite3_step(st.s) != SQLITE_DONE) throw InputError(path_, std::string("audit write failed: ") + sqlite3_errmsg(db_));
}

std::vector<AuditEntry> AccessDb::RecentAudit(std::size_t limit) const {
  std::lock_guard lock(mutex_);
  Statement st(db_,
               "SELECT id, time_utc, unix_s, user, role, remote, action, target, detail, outcome FROM audit "
               "ORDER BY id DESC LIMIT ?1",
               path_);
  sqlite3_bind_int64(st.s, 1, static_cast<sqlite3_int64>(limit));
  std::vector<AuditEntry> out;
  while (sqlite3_step(st.s) == SQLITE_ROW) {
    AuditEntry e;
    e.id = sqlite3_column_int64(st.s, 0);
    e.time_utc = st.Text(1);
    e.unix_s = sqlite3_column_double(st.s, 2);
    e.user = st.Text(3);
    e.role = st.Text(4);
    e.remote = st.Text(5);
    e.action = st.Text(6);
    e.target = st.Text(7);
    e.detail = st.Text(8);
    e.outcome = st.Text(9);
    out.push_back(std::move(e));
  }
  return out;
}

}  // namespace trueaxis::web
