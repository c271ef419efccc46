#include "trueaxis/store/history_db.hpp"

#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "test_dir.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::store {
namespace {

using testing::TempDirTest;
using HistoryDbTest = TempDirTest;

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void Fill(HistoryDb& db) {
  std::vector<HistoryRecord> batch;
  for (int i = 0; i < 100; ++i) {
    const double t = 1000.0 + i;
    batch.push_back(HistoryRecord::Temperature(t, "x_nut", 20 + 0.01 * i, 20 + 0.009 * i, i == 50 ? "stuck" : "ok"));
    batch.push_back(HistoryRecord::Temperature(t, "ambient", 19.5, 19.5, "ok"));
    batch.push_back(HistoryRecord::Compensation(t, "X", 100.0 + i, -0.5 * i, "active"));
  }
  batch.push_back(HistoryRecord::Alarm(1050, "warning", "x_nut", "stuck: no change, x_bearing moved 0.8 °C"));
  batch.push_back(HistoryRecord::ModelChange(1010, std::string(64, 'a'), "r2", "fit after warm-up, \"day 2\""));
  db.InsertBatch(batch);
}

TEST_F(HistoryDbTest, StoresAndQueriesByTimeRangeAndChannel) {
  const auto path = Path("h.db");
  {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    EXPECT_EQ(db.schema_version(), HistoryDb::kSchemaVersion);
    Fill(db);
  }
  HistoryDb db(path, HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(db.Channels(), (std::vector<std::string>{"ambient", "x_nut"}));
  EXPECT_EQ(db.Axes(), (std::vector<std::string>{"X"}));
  const auto all = db.QueryTemperatures({});
  EXPECT_EQ(all.size(), 200u);
  const auto window = db.QueryTemperatures({1010, 1019.5}, {"x_nut"});
  ASSERT_EQ(window.size(), 10u);
  EXPECT_DOUBLE_EQ(window.front().time_s, 1010);
  EXPECT_DOUBLE_EQ(window.back().time_s, 1019);
  EXPECT_DOUBLE_EQ(window[3].raw_c, 20 + 0.01 * 13);
  EXPECT_DOUBLE_EQ(window[3].filtered_c, 20 + 0.009 * 13);
  for (const auto& r : window) EXPECT_EQ(r.channel, "x_nut");
  const auto both = db.QueryTemperatures({1050, 1050});
  ASSERT_EQ(both.size(), 2u);  // inclusive bounds, ordered by time then channel
  EXPECT_EQ(both[0].channel, "ambient");
  EXPECT_EQ(both[1].status, "stuck");
  EXPECT_EQ(db.QueryTemperatures({}, {}, 7).size(), 7u);
  EXPECT_TRUE(db.QueryTemperatures({5000, 6000}).empty());
  const auto comp = db.QueryCompensation({1090, 2000}, {"X"});
  ASSERT_EQ(comp.size(), 10u);
  EXPECT_DOUBLE_EQ(comp[0].correction_um, -45);
  EXPECT_DOUBLE_EQ(comp[0].position_mm, 190);
  EXPECT_EQ(comp[0].state, "active");
  const auto alarms = db.QueryAlarms({});
  ASSERT_EQ(alarms.size(), 1u);
  EXPECT_EQ(alarms[0].message, "stuck: no change, x_bearing moved 0.8 °C");
  const auto models = db.QueryModelChanges({});
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].sha256, std::string(64, 'a'));
  EXPECT_EQ(models[0].revision, "r2");
  const auto summary = db.Summary();
  EXPECT_EQ(summary.temperature.rows, 200);
  EXPECT_DOUBLE_EQ(summary.temperature.first_time_s, 1000);
  EXPECT_DOUBLE_EQ(summary.temperature.last_time_s, 1099);
  EXPECT_NE(summary.BriefReport().find("x_nut"), std::string::npos);
}

TEST_F(HistoryDbTest, UnknownChannelIsAClearError) {
  const auto path = Path("h.db");
  {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    Fill(db);
  }
  HistoryDb db(path, HistoryDb::Mode::kReadOnly);
  try {
    db.QueryTemperatures({}, {"x_nut", "y_nut"});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "channels");
    EXPECT_NE(e.message().find("y_nut"), std::string::npos);
    EXPECT_NE(e.message().find("ambient, x_nut"), std::string::npos);
  }
  EXPECT_THROW(db.QueryCompensation({}, {"Q"}), InputError);
}

TEST_F(HistoryDbTest, NonFiniteValuesComeBackAsNaN) {
  const auto path = Path("h.db");
  HistoryDb db(path, HistoryDb::Mode::kReadWrite);
  std::vector<HistoryRecord> batch = {HistoryRecord::Temperature(1, "a", NAN, INFINITY, "hardware_fault")};
  db.InsertBatch(batch);
  const auto rows = db.QueryTemperatures({});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_TRUE(std::isnan(rows[0].raw_c));
  EXPECT_TRUE(std::isnan(rows[0].filtered_c));
}

TEST_F(HistoryDbTest, UsesWalAndMarksTheFileAsOurs) {
  const auto path = Path("h.db");
  { HistoryDb db(path, HistoryDb::Mode::kReadWrite); }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  auto pragma = [&](const char* sql) {
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(raw, sql, -1, &s, nullptr);
    std::string v;
    if (sqlite3_step(s) == SQLITE_ROW) v = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
    return v;
  };
  EXPECT_EQ(pragma("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(pragma("PRAGMA application_id"), std::to_string(HistoryDb::kApplicationId));
  EXPECT_EQ(pragma("PRAGMA user_version"), std::to_string(HistoryDb::kSchemaVersion));
  EXPECT_EQ(pragma("SELECT value FROM meta WHERE key = 'application'"), "trueaxis history");
  sqlite3_close(raw);
}

TEST_F(HistoryDbTest, RefusesGarbageAndLeavesItUntouched) {
  const auto path = Path("garbage.db");
  std::string bytes(8192, '\0');
  std::mt19937 rng(3);
  for (auto& b : bytes) b = static_cast<char>(rng());
  WriteTextFile(path, bytes);
  for (auto mode : {HistoryDb::Mode::kReadWrite, HistoryDb::Mode::kReadOnly}) {
    try {
      HistoryDb db(path, mode);
      FAIL() << "opened garbage";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("garbage.db"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find("not a trueaxis history database"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not modified"), std::string::npos);
    }
    EXPECT_EQ(FileBytes(path), bytes);
  }
  EXPECT_FALSE(std::filesystem::exists(path + "-wal"));
}

TEST_F(HistoryDbTest, RefusesAnotherApplicationsDatabase) {
  const auto path = Path("other.db");
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  sqlite3_exec(raw, "CREATE TABLE invoices(id INTEGER, amount REAL); INSERT INTO invoices VALUES (1, 9.5);", nullptr, nullptr, nullptr);
  sqlite3_close(raw);
  const std::string before = FileBytes(path);
  try {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("another application"), std::string::npos) << e.what();
  }
  EXPECT_EQ(FileBytes(path), before);
}

TEST_F(HistoryDbTest, RefusesNewerSchemaAndMissingOrEmptyFilesReadOnly) {
  const auto path = Path("h.db");
  { HistoryDb db(path, HistoryDb::Mode::kReadWrite); }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  sqlite3_exec(raw, "PRAGMA user_version = 99", nullptr, nullptr, nullptr);
  sqlite3_close(raw);
  try {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("newer trueaxis"), std::string::npos) << e.what();
  }
  EXPECT_THROW(HistoryDb(Path("missing.db"), HistoryDb::Mode::kReadOnly), InputError);
  EXPECT_FALSE(std::filesystem::exists(Path("missing.db")));  // never created by a reader
  WriteTextFile(Path("empty.db"), "");
  EXPECT_THROW(HistoryDb(Path("empty.db"), HistoryDb::Mode::kReadOnly), InputError);
  EXPECT_THROW(HistoryDb(dir_.string(), HistoryDb::Mode::kReadOnly), InputError);
}

TEST_F(HistoryDbTest, TruncatedDatabaseGivesAnErrorNotACrash) {
  const auto path = Path("h.db");
  {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    std::vector<HistoryRecord> batch;
    for (int i = 0; i < 20000; ++i) batch.push_back(HistoryRecord::Temperature(i, "c" + std::to_string(i % 8), 20, 20, "ok"));
    db.InsertBatch(batch);
  }
  // Checkpointed and closed; now cut the file in the middle of its pages.
  const std::string bytes = FileBytes(path);
  ASSERT_GT(bytes.size(), 65536u);
  const std::string cut = bytes.substr(0, bytes.size() / 2 + 100);
  WriteTextFile(path, cut);
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
  bool failed_cleanly = false;
  try {
    HistoryDb db(path, HistoryDb::Mode::kReadOnly);
    db.QueryTemperatures({});
    db.Summary();
  } catch (const std::exception& e) {
    failed_cleanly = std::string(e.what()).find("h.db") != std::string::npos;
  }
  EXPECT_TRUE(failed_cleanly);
  EXPECT_EQ(FileBytes(path), cut);
}

}  // namespace
}  // namespace trueaxis::store
