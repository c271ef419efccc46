#include <sqlite3.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "test_dir.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/signal/temperature_monitor.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {
namespace {

using CalibrationStoreTest = testing::TempDirTest;

signal::CalibrationSet MakeSet(double gain, double offset, const char* session) {
  signal::CalibrationSet set;
  set.reference = "ref";
  set.session = session;
  set.sensors["x_nut"].calibration = {gain, offset};
  set.sensors["x_nut"].points = 12;
  set.sensors["x_nut"].gain_fitted = true;
  set.sensors["ambient"].calibration = {1.0, 0.1};
  return set;
}

TEST_F(CalibrationStoreTest, NewestCalibrationPerSensorIsReturned) {
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadWrite);
  EXPECT_TRUE(db.LatestCalibration().sensors.empty());
  db.InsertCalibration(1000, MakeSet(1.01, -0.2, "monday.csv"));
  signal::CalibrationSet later;
  later.reference = "ref2";
  later.session = "friday.csv";
  later.sensors["x_nut"].calibration = {0.99, 0.3};
  db.InsertCalibration(2000, later);
  const auto latest = db.LatestCalibration();
  ASSERT_EQ(latest.sensors.size(), 2u);
  EXPECT_DOUBLE_EQ(latest.sensors.at("x_nut").calibration.gain, 0.99);
  EXPECT_DOUBLE_EQ(latest.sensors.at("x_nut").calibration.offset_c, 0.3);
  EXPECT_DOUBLE_EQ(latest.sensors.at("ambient").calibration.offset_c, 0.1);  // only calibrated on monday
  EXPECT_EQ(latest.reference, "ref2");
  EXPECT_EQ(db.Summary().calibration.rows, 3);
  // Ready for the monitor.
  signal::TemperatureMonitor mon({"x_nut", "ambient"});
  EXPECT_TRUE(mon.SetCalibration(latest).empty());
  std::vector<hw::RawTemperature> raw = {{30.0, false}, {20.0, false}};
  mon.Update(0, raw);
  EXPECT_DOUBLE_EQ(mon.reading(0).calibrated_c, 0.99 * 30 + 0.3);
}

TEST_F(CalibrationStoreTest, SchemaOneDatabaseIsMigratedKeepingItsData) {
  const auto path = Path("v1.db");
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw, HistoryDb::MigrationSteps()[0], nullptr, nullptr, nullptr), SQLITE_OK);
  const std::string pragmas = "PRAGMA application_id = " + std::to_string(HistoryDb::kApplicationId) + "; PRAGMA user_version = 1;" +
                              "INSERT INTO channel(id, name) VALUES (1, 'x_nut');"
                              "INSERT INTO temperature VALUES (5.0, 1, 24.5, 24.4, 'ok');";
  ASSERT_EQ(sqlite3_exec(raw, pragmas.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
  sqlite3_close(raw);
  // A reader does not migrate: it says what to do.
  try {
    HistoryDb db(path, HistoryDb::Mode::kReadOnly);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs migrating"), std::string::npos) << e.what();
  }
  {
    HistoryDb db(path, HistoryDb::Mode::kReadWrite);
    EXPECT_EQ(db.schema_version(), 2);
    db.InsertCalibration(10, MakeSet(1.02, 0, "s.csv"));
  }
  HistoryDb db(path, HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(db.schema_version(), 2);
  const auto rows = db.QueryTemperatures({});
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].channel, "x_nut");
  EXPECT_DOUBLE_EQ(rows[0].filtered_c, 24.4);
  EXPECT_DOUBLE_EQ(db.LatestCalibration().sensors.at("x_nut").calibration.gain, 1.02);
}

TEST_F(CalibrationStoreTest, CalibrateCliStoresIntoTheHistoryDatabase) {
  WriteTextFile(Path("s.csv"), "ref,x_nut\n20,19.5\n30,29.4\n40,39.3\n");
  auto r = testing::RunCli("calibrate --session " + Path("s.csv") + " --reference ref --out " + Path("cal.json") +
                           " --db " + Path("h.db"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("stored in"), std::string::npos);
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  const auto set = db.LatestCalibration();
  ASSERT_EQ(set.sensors.count("x_nut"), 1u);
  EXPECT_NEAR(set.sensors.at("x_nut").calibration.Apply(29.4), 30.0, 0.02);
  // A foreign file as --db: refused before anything is written.
  WriteTextFile(Path("notes.txt"), "not a database");
  r = testing::RunCli("calibrate --session " + Path("s.csv") + " --reference ref --out " + Path("cal2.json") +
                      " --db " + Path("notes.txt"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(std::filesystem::exists(Path("cal2.json")));
  EXPECT_EQ(ReadTextFile(Path("notes.txt")), "not a database");
}

}  // namespace
}  // namespace trueaxis::store
