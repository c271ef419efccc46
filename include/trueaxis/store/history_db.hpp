#pragma once
// HistoryDb: the temperature history database of seed 000 ("溫度歷史記錄數據庫")
// on SQLite: every temperature reading (raw, filtered, status), every
// compensation value per axis, alarms and model changes, retrievable by time
// range and channel. Schema and migrations: docs/history.md.
//
// One HistoryDb is one connection; use it from one thread at a time. The
// real-time loop never touches it: it pushes records to a HistoryWriter,
// whose thread owns a HistoryDb.
//
// Opening is careful: a file that is not a trueaxis history database (not
// SQLite, corrupt, another program's database, a newer schema) is refused
// with an InputError naming the file, and is never written to.
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "trueaxis/signal/calibration.hpp"
#include "trueaxis/store/history_record.hpp"
#include "trueaxis/store/history_sink.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace trueaxis::store {

struct TimeRange {
  double from_s = -std::numeric_limits<double>::infinity();  // inclusive
  double to_s = std::numeric_limits<double>::infinity();     // inclusive
};

struct TemperatureRow {
  double time_s = 0;
  std::string channel;
  double raw_c = 0;
  double filtered_c = 0;
  std::string status;
};
struct CompensationRow {
  double time_s = 0;
  std::string axis;
  double position_mm = 0;
  double correction_um = 0;
  std::string state;
};
struct AlarmRow {
  double time_s = 0;
  std::string severity;
  std::string source;
  std::string message;
};
struct ModelChangeRow {
  double time_s = 0;
  std::string sha256;
  std::string revision;
  std::string note;
};

struct TableSummary {
  std::int64_t rows = 0;
  double first_time_s = 0;  // meaningful when rows > 0
  double last_time_s = 0;
};
struct HistorySummary {
  std::string path;
  int schema_version = 0;
  TableSummary temperature, compensation, alarm, model_change, calibration;
  std::vector<std::pair<std::string, std::int64_t>> readings_per_channel;
  std::vector<std::string> axes;
  std::string BriefReport() const;
};

class HistoryDb : public HistorySink {
 public:
  enum class Mode { kReadOnly, kReadWrite };  // kReadWrite creates a missing file
  static constexpr int kSchemaVersion = 2;
  // The SQL of each migration step (step i: schema i -> i + 1), for tests and tools.
  static std::span<const char* const> MigrationSteps();
  static constexpr std::int32_t kApplicationId = 0x54415848;  // "TAXH"

  HistoryDb(const std::string& path, Mode mode);
  ~HistoryDb() override;
  HistoryDb(const HistoryDb&) = delete;
  HistoryDb& operator=(const HistoryDb&) = delete;

  const std::string& path() const { return path_; }
  int schema_version() const { return schema_version_; }

  // Writes all records in one transaction (all or nothing).
  void InsertBatch(std::span<const HistoryRecord> records) override;
  std::string Describe() const override { return path_; }

  std::vector<std::string> Channels() const;
  std::vector<std::string> Axes() const;

  // Rows ordered by time (then channel). Empty `channels` = all. Names that
  // do not exist throw InputError (field "channels") listing the known ones.
  void ForEachTemperature(const TimeRange& range, const std::vector<std::string>& channels,
                          const std::function<void(const TemperatureRow&)>& fn) const;
  std::vector<TemperatureRow> QueryTemperatures(const TimeRange& range, const std::vector<std::string>& channels = {},
                                                std::size_t limit = 0) const;
  void ForEachCompensation(const TimeRange& range, const std::vector<std::string>& axes,
                           const std::function<void(const CompensationRow&)>& fn) const;
  std::vector<CompensationRow> QueryCompensation(const TimeRange& range, const std::vector<std::string>& axes = {}) const;
  std::vector<AlarmRow> QueryAlarms(const TimeRange& range) const;
  std::vector<ModelChangeRow> QueryModelChanges(const TimeRange& range) const;

  HistorySummary Summary() const;

  // Sensor calibrations (schema 2): stored synchronously (rare event), one
  // transaction; LatestCalibration() gives the newest calibration per sensor,
  // ready for TemperatureMonitor::SetCalibration().
  void InsertCalibration(double time_s, const signal::CalibrationSet& set);
  signal::CalibrationSet LatestCalibration() const;

 private:
  void Validate(Mode mode, bool fresh);
  void Migrate(int from_version);
  void Exec(const char* sql);
  [[noreturn]] void Fail(const std::string& what) const;
  sqlite3_stmt* Prepare(const char* sql) const;
  std::int64_t NameId(const char* table, const char* name);
  std::vector<std::int64_t> ResolveNames(const char* table, const std::vector<std::string>& names,
                                         const char* field) const;
  // Runs `sql` with ?1..?2 bound to the time range and ?3.. to `ids`, calling
  // on_row for every result row; a failing step throws.
  void ForEachRow(const std::string& sql, const TimeRange& range, const std::vector<std::int64_t>& ids,
                  const std::function<void(sqlite3_stmt*)>& on_row) const;

  std::string path_;
  sqlite3* db_ = nullptr;
  int schema_version_ = 0;
  bool read_only_ = false;
  // Writer-side caches of name -> id (channel, axis tables): hashed, since a shop-wide history
  // holds thousands of names and every row looks its name up. `added` lists the names the batch
  // being written added, so a rolled-back batch takes them out again.
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  struct NameIds {
    std::unordered_map<std::string, std::int64_t, NameHash, std::equal_to<>> ids;
    std::vector<std::string> added;
  };
  NameIds channel_ids_, axis_ids_;
  sqlite3_stmt* insert_temperature_ = nullptr;
  sqlite3_stmt* insert_compensation_ = nullptr;
  sqlite3_stmt* insert_alarm_ = nullptr;
  sqlite3_stmt* insert_model_ = nullptr;
};

}  // namespace trueaxis::store
