#include "trueaxis/store/history_db.hpp"

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/time_text.hpp"

namespace trueaxis::store {
namespace {

// Migrations: kMigrations[i] brings the schema from version i to i + 1.
// Append a step for every schema change; never edit a released step.
constexpr const char* kMigrations[] = {
    // 0 -> 1: the first schema.
    R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE channel(id INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE axis(id INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE temperature(
  time_s REAL NOT NULL,
  channel_id INTEGER NOT NULL REFERENCES channel(id),
  raw_c REAL,
  filtered_c REAL,
  status TEXT NOT NULL);
CREATE INDEX temperature_by_channel_time ON temperature(channel_id, time_s);
CREATE INDEX temperature_by_time ON temperature(time_s);
CREATE TABLE compensation(
  time_s REAL NOT NULL,
  axis_id INTEGER NOT NULL REFERENCES axis(id),
  position_mm REAL,
  correction_um REAL NOT NULL,
  state TEXT NOT NULL);
CREATE INDEX compensation_by_axis_time ON compensation(axis_id, time_s);
CREATE TABLE alarm(time_s REAL NOT NULL, severity TEXT NOT NULL, source TEXT NOT NULL, message TEXT NOT NULL);
CREATE INDEX alarm_by_time ON alarm(time_s);
CREATE TABLE model_change(time_s REAL NOT NULL, sha256 TEXT NOT NULL, revision TEXT NOT NULL, note TEXT NOT NULL);
INSERT INTO meta(key, value) VALUES ('application', 'trueaxis history'), ('time_unit', 'seconds since 1970-01-01T00:00:00Z');
)sql",
    // 1 -> 2: sensor calibrations against a reference sensor (seed 000 "自動標定");
    // the newest row per sensor is the one in force.
    R"sql(
CREATE TABLE calibration(
  time_s REAL NOT NULL,
  sensor TEXT NOT NULL,
  reference TEXT NOT NULL,
  gain REAL NOT NULL,
  offset_c REAL NOT NULL,
  gain_fitted INTEGER NOT NULL,
  points INTEGER NOT NULL,
  reference_span_c REAL,
  rms_residual_c REAL,
  max_abs_residual_c REAL,
  max_abs_error_before_c REAL,
  session TEXT NOT NULL);
CREATE INDEX calibration_by_sensor_time ON calibration(sensor, time_s);
)sql",
};
static_assert(std::size(kMigrations) == HistoryDb::kSchemaVersion);

// Finite values only: SQLite has no NaN, it would store NULL anyway.
void BindDouble(sqlite3_stmt* s, int i, double v) {
  if (std::isfinite(v)) sqlite3_bind_double(s, i, v);
  else sqlite3_bind_null(s, i);
}

double ColumnDouble(sqlite3_stmt* s, int i) {
  return sqlite3_column_type(s, i) == SQLITE_NULL ? NAN : sqlite3_column_double(s, i);
}

std::string ColumnText(sqlite3_stmt* s, int i) {
  const auto* t = sqlite3_column_text(s, i);
  return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
}

struct Statement {
  sqlite3_stmt* s = nullptr;
  ~Statement() { sqlite3_finalize(s); }
};

}  // namespace

std::span<const char* const> HistoryDb::MigrationSteps() { return kMigrations; }

std::string HistorySummary::BriefReport() const {
  auto line = [](const char* what, const TableSummary& t) {
    if (t.rows == 0) return fmt::format("  {:<14} 0 rows\n", what);
    return fmt::format("  {:<14} {} rows, {} .. {}\n", what, t.rows, FormatUtc(t.first_time_s), FormatUtc(t.last_time_s));
  };
  std::string out = fmt::format("{}: trueaxis history database, schema {}\n", path, schema_version);
  out += line("temperature", temperature);
  out += line("compensation", compensation);
  out += line("alarm", alarm);
  out += line("model_change", model_change);
  out += line("calibration", calibration);
  for (const auto& [name, n] : readings_per_channel) out += fmt::format("    channel {:<16} {} readings\n", name, n);
  if (!axes.empty()) {
    out += "    axes:";
    for (const auto& a : axes) out += " " + a;
    out += "\n";
  }
  return out;
}

namespace {

// What the file's first 100 bytes (the SQLite header, sqlite.org/fileformat.html) say against the
// file itself, checked before SQLite opens it: SQLite, even read-only, may leave -wal/-shm files
// beside a file it then finds damaged, next to a message that the file was not modified.
std::optional<std::string> SqliteHeaderProblem(const std::string& path, std::uintmax_t file_size) {
  unsigned char h[100] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (in.gcount() < 100 || std::memcmp(h, "SQLite format 3", 16) != 0)
    return std::string("not a trueaxis history database (no SQLite header)");
  const auto be32 = [&](int at) {
    return (std::uint32_t{h[at]} << 24) | (std::uint32_t{h[at + 1]} << 16) | (std::uint32_t{h[at + 2]} << 8) | h[at + 3];
  };
  const std::uint32_t page_size = h[16] == 0 && h[17] == 1 ? 65536u : (std::uint32_t{h[16]} << 8) | h[17];
  const std::uint32_t pages = be32(28);
  // The in-header size is valid when non-zero and the change counter matches version-valid-for.
  if (pages > 0 && be32(24) == be32(92) && std::uintmax_t{pages} * page_size > file_size)
    return fmt::format("the history database is damaged: cut short (its header says {} pages of {} bytes, the file "
                       "holds {} bytes)", pages, page_size, file_size);
  return std::nullopt;
}

}  // namespace

HistoryDb::HistoryDb(const std::string& path, Mode mode) : path_(path), read_only_(mode == Mode::kReadOnly) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool exists = fs::exists(path, ec);
  if (exists && fs::is_directory(path, ec)) throw InputError(path, "is a directory, not a history database");
  if (!exists && read_only_) throw InputError(path, "no such history database");
  const bool fresh = !exists || fs::file_size(path, ec) == 0;
  if (read_only_ && !fresh)
    if (auto why = SqliteHeaderProblem(path, fs::file_size(path, ec)))
      throw InputError(path, *why + "; the file was not modified");
  int flags = read_only_ ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
  if (!exists && !read_only_) flags |= SQLITE_OPEN_CREATE;
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  if (rc != SQLITE_OK) {
    std::string msg = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close(db_);
    db_ = nullptr;
    throw InputError(path, "cannot open history database: " + msg);
  }
  sqlite3_busy_timeout(db_, 5000);
  try {
    Validate(mode, fresh);
  } catch (...) {
    sqlite3_close(db_);
    db_ = nullptr;
    throw;
  }
}

HistoryDb::~HistoryDb() {
  sqlite3_finalize(insert_temperature_);
  sqlite3_finalize(insert_compensation_);
  sqlite3_finalize(insert_alarm_);
  sqlite3_finalize(insert_model_);
  if (db_) sqlite3_close(db_);
}

void HistoryDb::Fail(const std::string& what) const {
  // A damaged file (pages overwritten, cut short) shows only when its pages are read: that is bad input
  // (the user's file), not a program failure.
  const int code = db_ ? (sqlite3_errcode(db_) & 0xff) : SQLITE_OK;
  if (code == SQLITE_CORRUPT || code == SQLITE_NOTADB)
    throw InputError(path_, fmt::format("the history database is damaged ({}: {}){}", what, sqlite3_errmsg(db_),
                                        read_only_ ? "; the file was not modified" : ""));
  throw std::runtime_error(fmt::format("{}: {}: {}", path_, what, db_ ? sqlite3_errmsg(db_) : "no connection"));
}

void HistoryDb::Exec(const char* sql) {
  char* err = nullptr;
  if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
    std::string msg = err ? err : "unknown error";
    sqlite3_free(err);
    throw std::runtime_error(fmt::format("{}: {}", path_, msg));
  }
}

sqlite3_stmt* HistoryDb::Prepare(const char* sql) const {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db_, sql, -1, &s, nullptr) != SQLITE_OK) Fail("cannot prepare statement");
  return s;
}

void HistoryDb::Validate(Mode mode, bool fresh) {
  // Read-only checks first: nothing is written until we know the file is ours.
  auto refuse = [&](const std::string& why) {
    throw InputError(path_, why + "; the file was not modified");
  };
  std::int64_t app_id = 0, user_version = 0, objects = 0;
  {
    Statement st;
    if (sqlite3_prepare_v2(db_, "PRAGMA application_id", -1, &st.s, nullptr) != SQLITE_OK ||
        sqlite3_step(st.s) != SQLITE_ROW)
      refuse(fmt::format("not a trueaxis history database (not readable as SQLite: {})", sqlite3_errmsg(db_)));
    app_id = sqlite3_column_int64(st.s, 0);
  }
  {
    Statement st;
    if (sqlite3_prepare_v2(db_, "PRAGMA user_version", -1, &st.s, nullptr) != SQLITE_OK || sqlite3_step(st.s) != SQLITE_ROW)
      refuse(fmt::format("cannot read the schema version: {}", sqlite3_errmsg(db_)));
    user_version = sqlite3_column_int64(st.s, 0);
  }
  {
    Statement st;
    if (sqlite3_prepare_v2(db_, "SELECT count(*) FROM sqlite_master", -1, &st.s, nullptr) != SQLITE_OK ||
        sqlite3_step(st.s) != SQLITE_ROW)
      refuse(fmt::format("not a trueaxis history database (corrupt or not SQLite: {})", sqlite3_errmsg(db_)));
    objects = sqlite3_column_int64(st.s, 0);
  }
  const bool empty = app_id == 0 && objects == 0;
  if (empty) {
    if (read_only_) refuse(fresh ? "empty file, not a trueaxis history database" : "empty SQLite database, not a trueaxis history database");
  } else if (app_id != kApplicationId) {
    refuse(fmt::format("an SQLite database of another application (application_id 0x{:08x}, {} schema objects), "
                       "not a trueaxis history database",
                       static_cast<std::uint32_t>(app_id), objects));
  } else if (user_version > kSchemaVersion) {
    refuse(fmt::format("written by a newer trueaxis (schema {}; this program reads up to schema {})", user_version,
                       kSchemaVersion));
  }
  if (read_only_) {
    if (user_version < kSchemaVersion)
      refuse(fmt::format("schema {} needs migrating to {}: open it once for writing (e.g. with the runtime)",
                         user_version, kSchemaVersion));
    schema_version_ = static_cast<int>(user_version);
    return;
  }
  Exec("PRAGMA journal_mode=WAL");
  Exec("PRAGMA synchronous=NORMAL");
  Exec("PRAGMA foreign_keys=ON");
  if (user_version < kSchemaVersion) Migrate(static_cast<int>(user_version));
  schema_version_ = kSchemaVersion;
}

void HistoryDb::Migrate(int from_version) {
  Exec("BEGIN IMMEDIATE");
  try {
    for (int v = from_version; v < kSchemaVersion; ++v) Exec(kMigrations[v]);
    Exec(fmt::format("PRAGMA application_id = {}", kApplicationId).c_str());
    Exec(fmt::format("PRAGMA user_version = {}", kSchemaVersion).c_str());
    Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::int64_t HistoryDb::NameId(const char* table, const char* name) {
  NameIds& cache = std::string_view(table) == "channel" ? channel_ids_ : axis_ids_;
  if (const auto it = cache.ids.find(std::string_view(name)); it != cache.ids.end()) return it->second;
  const std::string insert = fmt::format("INSERT OR IGNORE INTO {}(name) VALUES (?1)", table);
  const std::string select = fmt::format("SELECT id FROM {} WHERE name = ?1", table);
  {
    Statement st;
    st.s = Prepare(insert.c_str());
    sqlite3_bind_text(st.s, 1, name, -1, SQLITE_TRANSIENT);
    if (sqlite3_step(st.s) != SQLITE_DONE) Fail(fmt::format("cannot add {} '{}'", table, name));
  }
  Statement st;
  st.s = Prepare(select.c_str());
  sqlite3_bind_text(st.s, 1, name, -1, SQLITE_TRANSIENT);
  if (sqlite3_step(st.s) != SQLITE_ROW) Fail(fmt::format("cannot find {} '{}'", table, name));
  const std::int64_t id = sqlite3_column_int64(st.s, 0);
  cache.ids.emplace(name, id);
  cache.added.emplace_back(name);
  return id;
}

void HistoryDb::InsertBatch(std::span<const HistoryRecord> records) {
  if (read_only_) throw std::logic_error(path_ + ": opened read-only");
  if (records.empty()) return;
  if (!insert_temperature_) {
    insert_temperature_ = Prepare("INSERT INTO temperature(time_s, channel_id, raw_c, filtered_c, status) VALUES (?1,?2,?3,?4,?5)");
    insert_compensation_ = Prepare("INSERT INTO compensation(time_s, axis_id, position_mm, correction_um, state) VALUES (?1,?2,?3,?4,?5)");
    insert_alarm_ = Prepare("INSERT INTO alarm(time_s, severity, source, message) VALUES (?1,?2,?3,?4)");
    insert_model_ = Prepare("INSERT INTO model_change(time_s, sha256, revision, note) VALUES (?1,?2,?3,?4)");
  }
  Exec("BEGIN IMMEDIATE");
  // Name caches may gain entries that a rollback removes from the tables.
  channel_ids_.added.clear();
  axis_ids_.added.clear();
  try {
    for (const auto& r : records) {
      sqlite3_stmt* s = nullptr;
      switch (r.kind) {
        case RecordKind::kTemperature:
          s = insert_temperature_;
          sqlite3_bind_int64(s, 2, NameId("channel", r.name));
          BindDouble(s, 3, r.a);
          BindDouble(s, 4, r.b);
          sqlite3_bind_text(s, 5, r.word, -1, SQLITE_STATIC);
          break;
        case RecordKind::kCompensation:
          s = insert_compensation_;
          sqlite3_bind_int64(s, 2, NameId("axis", r.name));
          BindDouble(s, 3, r.a);
          BindDouble(s, 4, r.b);
          sqlite3_bind_text(s, 5, r.word, -1, SQLITE_STATIC);
          break;
        case RecordKind::kAlarm:
          s = insert_alarm_;
          sqlite3_bind_text(s, 2, r.word, -1, SQLITE_STATIC);
          sqlite3_bind_text(s, 3, r.name, -1, SQLITE_STATIC);
          sqlite3_bind_text(s, 4, r.text, -1, SQLITE_STATIC);
          break;
        case RecordKind::kModelChange:
          s = insert_model_;
          sqlite3_bind_text(s, 2, r.word, -1, SQLITE_STATIC);
          sqlite3_bind_text(s, 3, r.name, -1, SQLITE_STATIC);
          sqlite3_bind_text(s, 4, r.text, -1, SQLITE_STATIC);
          break;
      }
      sqlite3_bind_double(s, 1, r.time_s);
      const int rc = sqlite3_step(s);
      sqlite3_reset(s);
      sqlite3_clear_bindings(s);
      if (rc != SQLITE_DONE) Fail("cannot insert record");
    }
    Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    for (NameIds* cache : {&channel_ids_, &axis_ids_})
      for (const auto& name : cache->added) cache->ids.erase(name);
    throw;
  }
}

namespace {
std::vector<std::string> Names(const HistoryDb& db, sqlite3_stmt* s) {
  std::vector<std::string> out;
  while (sqlite3_step(s) == SQLITE_ROW) out.push_back(ColumnText(s, 0));
  return out;
}
}  // namespace

std::vector<std::string> HistoryDb::Channels() const {
  Statement st;
  st.s = Prepare("SELECT name FROM channel ORDER BY name");
  return Names(*this, st.s);
}

std::vector<std::string> HistoryDb::Axes() const {
  Statement st;
  st.s = Prepare("SELECT name FROM axis ORDER BY name");
  return Names(*this, st.s);
}

std::vector<std::int64_t> HistoryDb::ResolveNames(const char* table, const std::vector<std::string>& names,
                                                  const char* field) const {
  std::vector<std::int64_t> ids;
  if (names.empty()) return ids;
  const std::string select = fmt::format("SELECT id FROM {} WHERE name = ?1", table);
  for (const auto& name : names) {
    Statement st;
    st.s = Prepare(select.c_str());
    sqlite3_bind_text(st.s, 1, name.c_str(), -1, SQLITE_TRANSIENT);
    if (sqlite3_step(st.s) != SQLITE_ROW) {
      const auto known = std::string_view(table) == "channel" ? Channels() : Axes();
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError(path_, 0, field,
                       fmt::format("no {} '{}' in this database (known: {})", table, name, list.empty() ? "none" : list));
    }
    ids.push_back(sqlite3_column_int64(st.s, 0));
  }
  return ids;
}

namespace {
// "(?3,?4,...)" for an IN list starting at parameter `first`.
std::string InList(std::size_t n, int first) {
  std::string s = "(";
  for (std::size_t i = 0; i < n; ++i) s += fmt::format("{}?{}", i ? "," : "", first + static_cast<int>(i));
  return s + ")";
}
void BindRange(sqlite3_stmt* s, const TimeRange& r) {
  sqlite3_bind_double(s, 1, std::isfinite(r.from_s) ? r.from_s : -1e300);
  sqlite3_bind_double(s, 2, std::isfinite(r.to_s) ? r.to_s : 1e300);
}
}  // namespace

void HistoryDb::ForEachTemperature(const TimeRange& range, const std::vector<std::string>& channels,
                                   const std::function<void(const TemperatureRow&)>& fn) const {
  const auto ids = ResolveNames("channel", channels, "channels");
  std::string sql =
      "SELECT t.time_s, c.name, t.raw_c, t.filtered_c, t.status FROM temperature t JOIN channel c ON c.id = t.channel_id "
      "WHERE t.time_s BETWEEN ?1 AND ?2";
  if (!ids.empty()) sql += " AND t.channel_id IN " + InList(ids.size(), 3);
  sql += " ORDER BY t.time_s, c.name";
  TemperatureRow row;
  ForEachRow(sql, range, ids, [&](sqlite3_stmt* s) {
    row.time_s = sqlite3_column_double(s, 0);
    row.channel = ColumnText(s, 1);
    row.raw_c = ColumnDouble(s, 2);
    row.filtered_c = ColumnDouble(s, 3);
    row.status = ColumnText(s, 4);
    fn(row);
  });
}

void HistoryDb::ForEachRow(const std::string& sql, const TimeRange& range, const std::vector<std::int64_t>& ids,
                           const std::function<void(sqlite3_stmt*)>& on_row) const {
  Statement st;
  st.s = Prepare(sql.c_str());
  BindRange(st.s, range);
  for (std::size_t i = 0; i < ids.size(); ++i) sqlite3_bind_int64(st.s, 3 + static_cast<int>(i), ids[i]);
  int rc;
  while ((rc = sqlite3_step(st.s)) == SQLITE_ROW) on_row(st.s);
  if (rc != SQLITE_DONE) Fail("query failed");
}

std::vector<TemperatureRow> HistoryDb::QueryTemperatures(const TimeRange& range, const std::vector<std::string>& channels,
                                                         std::size_t limit) const {
  std::vector<TemperatureRow> rows;
  struct Enough {};
  try {
    ForEachTemperature(range, channels, [&](const TemperatureRow& r) {
      rows.push_back(r);
      if (limit && rows.size() >= limit) throw Enough{};
    });
  } catch (const Enough&) {
  }
  return rows;
}

void HistoryDb::ForEachCompensation(const TimeRange& range, const std::vector<std::string>& axes,
                                    const std::function<void(const CompensationRow&)>& fn) const {
  const auto ids = ResolveNames("axis", axes, "axes");
  std::string sql =
      "SELECT t.time_s, a.name, t.position_mm, t.correction_um, t.state FROM compensation t JOIN axis a ON a.id = t.axis_id "
      "WHERE t.time_s BETWEEN ?1 AND ?2";
  if (!ids.empty()) sql += " AND t.axis_id IN " + InList(ids.size(), 3);
  sql += " ORDER BY t.time_s, a.name";
  CompensationRow row;
  ForEachRow(sql, range, ids, [&](sqlite3_stmt* s) {
    row.time_s = sqlite3_column_double(s, 0);
    row.axis = ColumnText(s, 1);
    row.position_mm = ColumnDouble(s, 2);
    row.correction_um = ColumnDouble(s, 3);
    row.state = ColumnText(s, 4);
    fn(row);
  });
}

std::vector<CompensationRow> HistoryDb::QueryCompensation(const TimeRange& range, const std::vector<std::string>& axes) const {
  std::vector<CompensationRow> rows;
  ForEachCompensation(range, axes, [&](const CompensationRow& r) { rows.push_back(r); });
  return rows;
}

std::vector<AlarmRow> HistoryDb::QueryAlarms(const TimeRange& range) const {
  std::vector<AlarmRow> rows;
  ForEachRow("SELECT time_s, severity, source, message FROM alarm WHERE time_s BETWEEN ?1 AND ?2 ORDER BY time_s, rowid", range, {},
             [&](sqlite3_stmt* s) {
               rows.push_back({sqlite3_column_double(s, 0), ColumnText(s, 1), ColumnText(s, 2), ColumnText(s, 3)});
             });
  return rows;
}

std::vector<ModelChangeRow> HistoryDb::QueryModelChanges(const TimeRange& range) const {
  std::vector<ModelChangeRow> rows;
  ForEachRow("SELECT time_s, sha256, revision, note FROM model_change WHERE time_s BETWEEN ?1 AND ?2 ORDER BY time_s, rowid", range, {},
             [&](sqlite3_stmt* s) {
               rows.push_back({sqlite3_column_double(s, 0), ColumnText(s, 1), ColumnText(s, 2), ColumnText(s, 3)});
             });
  return rows;
}

HistorySummary HistoryDb::Summary() const {
  HistorySummary s;
  s.path = path_;
  s.schema_version = schema_version_;
  auto table = [&](const char* name) {
    TableSummary t;
    Statement st;
    const std::string sql = fmt::format("SELECT count(*), min(time_s), max(time_s) FROM {}", name);
    st.s = Prepare(sql.c_str());
    if (sqlite3_step(st.s) != SQLITE_ROW) Fail("summary failed");
    t.rows = sqlite3_column_int64(st.s, 0);
    t.first_time_s = sqlite3_column_double(st.s, 1);
    t.last_time_s = sqlite3_column_double(st.s, 2);
    return t;
  };
  s.temperature = table("temperature");
  s.compensation = table("compensation");
  s.alarm = table("alarm");
  s.model_change = table("model_change");
  s.calibration = table("calibration");
  Statement st;
  st.s = Prepare(
      "SELECT c.name, (SELECT count(*) FROM temperature t WHERE t.channel_id = c.id) FROM channel c ORDER BY c.name");
  while (sqlite3_step(st.s) == SQLITE_ROW) s.readings_per_channel.emplace_back(ColumnText(st.s, 0), sqlite3_column_int64(st.s, 1));
  s.axes = Axes();
  return s;
}

}  // namespace trueaxis::store

namespace trueaxis::store {

void HistoryDb::InsertCalibration(double time_s, const signal::CalibrationSet& set) {
  if (read_only_) throw std::logic_error(path_ + ": opened read-only");
  Statement st;
  st.s = Prepare(
      "INSERT INTO calibration(time_s, sensor, reference, gain, offset_c, gain_fitted, points, reference_span_c, "
      "rms_residual_c, max_abs_residual_c, max_abs_error_before_c, session) VALUES (?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12)");
  Exec("BEGIN IMMEDIATE");
  try {
    for (const auto& [sensor, fit] : set.sensors) {
      sqlite3_bind_double(st.s, 1, time_s);
      sqlite3_bind_text(st.s, 2, sensor.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(st.s, 3, set.reference.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_double(st.s, 4, fit.calibration.gain);
      sqlite3_bind_double(st.s, 5, fit.calibration.offset_c);
      sqlite3_bind_int(st.s, 6, fit.gain_fitted ? 1 : 0);
      sqlite3_bind_int(st.s, 7, fit.points);
      BindDouble(st.s, 8, fit.reference_span_c);
      BindDouble(st.s, 9, fit.rms_residual_c);
      BindDouble(st.s, 10, fit.max_abs_residual_c);
      BindDouble(st.s, 11, fit.max_abs_error_before_c);
      sqlite3_bind_text(st.s, 12, set.session.c_str(), -1, SQLITE_TRANSIENT);
      const int rc = sqlite3_step(st.s);
      sqlite3_reset(st.s);
      if (rc != SQLITE_DONE) Fail("cannot store calibration");
    }
    Exec("COMMIT");
  } catch (...) {
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

signal::CalibrationSet HistoryDb::LatestCalibration() const {
  // Newest row per sensor; ties (one session) broken by insertion order.
  Statement st;
  st.s = Prepare(
      "SELECT sensor, reference, gain, offset_c, gain_fitted, points, reference_span_c, rms_residual_c, "
      "max_abs_residual_c, max_abs_error_before_c, session, time_s FROM calibration c "
      "WHERE rowid = (SELECT rowid FROM calibration d WHERE d.sensor = c.sensor ORDER BY time_s DESC, rowid DESC LIMIT 1) "
      "ORDER BY time_s, sensor");
  signal::CalibrationSet set;
  int rc;
  while ((rc = sqlite3_step(st.s)) == SQLITE_ROW) {
    signal::CalibrationFit fit;
    fit.calibration.gain = sqlite3_column_double(st.s, 2);
    fit.calibration.offset_c = sqlite3_column_double(st.s, 3);
    fit.gain_fitted = sqlite3_column_int(st.s, 4) != 0;
    fit.points = sqlite3_column_int(st.s, 5);
    fit.reference_span_c = ColumnDouble(st.s, 6);
    fit.rms_residual_c = ColumnDouble(st.s, 7);
    fit.max_abs_residual_c = ColumnDouble(st.s, 8);
    fit.max_abs_error_before_c = ColumnDouble(st.s, 9);
    set.sensors[ColumnText(st.s, 0)] = fit;
    set.reference = ColumnText(st.s, 1);  // the newest row's reference wins
    set.session = ColumnText(st.s, 10);
  }
  if (rc != SQLITE_DONE) Fail("calibration query failed");
  return set;
}

}  // namespace trueaxis::store
