#pragma once
// PostgresHistorySink: the history on a PostgreSQL server (libpqxx), for a
// shop that outgrows one SQLite file. The schema mirrors the SQLite one
// (HistoryDb, docs/history.md): the same tables and columns, DOUBLE PRECISION
// for SQLite's REAL, BIGINT identities for its INTEGER PRIMARY KEYs, the
// schema version in meta('schema_version'). It lives in one PostgreSQL schema
// (namespace, default "public"), so one database can hold one history per
// machine (schema = machine name) as one SQLite file per machine would.
//
// Opening connects, then creates or migrates the tables under an advisory
// lock (two writers starting at once do not race); a schema holding other
// tables than a trueaxis history, or a newer schema version, is refused with
// an InputError naming the database and never written to.
//
// InsertBatch: one transaction per batch (COPY per table, names resolved
// first); all or nothing. A lost connection throws (the writer counts the
// batch as failed) and the next batch reconnects.
//
// One connection: use a sink from one thread at a time (the writer's thread owns it; read back
// through a second sink).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_sink.hpp"

namespace trueaxis::store {

struct PostgresHistoryOptions {
  std::string url;              // libpq URI: postgresql://user:password@host:port/db?host=/socket/dir
  std::string schema = "public";  // PostgreSQL schema (namespace) holding the tables
};

struct HistoryCounts {
  std::int64_t temperature = 0, compensation = 0, alarm = 0, model_change = 0, calibration = 0;
  std::int64_t channels = 0, axes = 0;
};

class PostgresHistorySink final : public HistorySink {
 public:
  static constexpr int kSchemaVersion = HistoryDb::kSchemaVersion;  // the same schema, step for step
  // The PostgreSQL dialect of each SQLite migration step (step i: schema i -> i + 1).
  static const std::vector<std::string>& MigrationSteps();

  explicit PostgresHistorySink(PostgresHistoryOptions options);  // connects and migrates; throws InputError
  ~PostgresHistorySink() override;
  PostgresHistorySink(const PostgresHistorySink&) = delete;
  PostgresHistorySink& operator=(const PostgresHistorySink&) = delete;

  void InsertBatch(std::span<const HistoryRecord> records) override;
  // The URL with any password replaced by "***", and the schema when not public.
  std::string Describe() const override;

  int schema_version() const { return schema_version_; }
  std::uint64_t reconnects() const { return reconnects_; }

  // Read back (tests, tools): rows per table, and temperature rows by time.
  HistoryCounts Counts();
  std::vector<TemperatureRow> QueryTemperatures(const TimeRange& range, std::size_t limit = 0);

 private:
  void Connect();
  void OpenOrMigrate();
  std::int64_t NameId(void* tx, const char* table, const char* name);
  PostgresHistoryOptions options_;
  std::string description_;
  struct Connection;  // pqxx::connection (an alias template in libpqxx 6, not forward-declarable)
  std::unique_ptr<Connection> conn_;
  int schema_version_ = 0;
  std::uint64_t reconnects_ = 0;
  std::vector<std::pair<std::string, std::int64_t>> channel_ids_, axis_ids_;
};

// Lets store::OpenHistorySink open postgresql:// URLs with PostgresHistorySink (once, before any
// open; trueaxis calls it at start).
void EnablePostgresHistory();

}  // namespace trueaxis::store
