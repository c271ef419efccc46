// The history on a real PostgreSQL 15 server started for this suite
// (postgres_server.hpp): schema created and migrated on open, one batch = one
// transaction, read back by the sink and by psql, foreign and newer schemas
// refused, a server that goes away and comes back. If PostgreSQL cannot be
// started the tests FAIL with the reason — they never pass silently.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "postgres_server.hpp"
#include "store/test_dir.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/store/open_history_sink.hpp"
#include "trueaxis/store_postgres/postgres_history_sink.hpp"

namespace trueaxis::store {
namespace {

class PostgresHistory : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    EnablePostgresHistory();
    server_ = new testing::PostgresServer();
    started_ = server_->Start();
  }
  static void TearDownTestSuite() {
    delete server_;  // stops the server and removes its directory, whatever the tests did
    server_ = nullptr;
  }
  void SetUp() override { ASSERT_TRUE(started_) << "PostgreSQL could not be started: " << server_->error(); }
  std::unique_ptr<PostgresHistorySink> Open(const std::string& schema) {
    return std::make_unique<PostgresHistorySink>(PostgresHistoryOptions{server_->Url(), schema});
  }
  // Which of the two refusals opening `schema` gives ("" when it opens, else the message).
  std::string OpenError(const std::string& schema) {
    try {
      Open(schema);
      return "";
    } catch (const InputError& e) {
      const std::string what = e.what();
      for (const char* reason : {"another application", "newer trueaxis"})
        if (what.find(reason) != std::string::npos) return reason;
      return what;
    }
  }
  static testing::PostgresServer* server_;
  static bool started_;
};
testing::PostgresServer* PostgresHistory::server_ = nullptr;
bool PostgresHistory::started_ = false;

TEST_F(PostgresHistory, WriterStoresEveryKindOfRecordReadBackBySinkAndPsql) {
  HistoryWriter writer(OpenHistorySink(server_->Url(), {"machine_a"}));
  for (int i = 0; i < 500; ++i) {
    writer.PushTemperature(1000.0 + i, "x_nut", 20.0 + 0.01 * i, 20.0 + 0.005 * i, "ok");
    writer.PushTemperature(1000.0 + i, "bed", 21.5, 21.5, "ok");
    writer.PushCompensation(1000.0 + i, "X", 0.5 * i, -1.25 * i, "active");
  }
  writer.PushTemperature(2000.0, "x_nut", std::nan(""), 20.0, "fault");  // NaN is stored as NULL, as in SQLite
  writer.PushAlarm(1500.0, "warning", "x_nut", "spike rejected: it's \"quoted\"\ttabbed\\ and on\ntwo lines");
  writer.PushModelChange(1600.0, "ab12", "rev 2", "refit after spindle service");
  writer.Flush();
  const auto stats = writer.Stats();
  EXPECT_EQ(stats.written, 1503u) << stats.BriefReport();
  EXPECT_EQ(stats.failed, 0u) << stats.last_error;
  writer.Close();

  auto sink = Open("machine_a");
  const auto c = sink->Counts();
  EXPECT_EQ(c.temperature, 1001);
  EXPECT_EQ(c.compensation, 500);
  EXPECT_EQ(c.alarm, 1);
  EXPECT_EQ(c.model_change, 1);
  EXPECT_EQ(c.channels, 2);
  EXPECT_EQ(c.axes, 1);
  const auto rows = sink->QueryTemperatures({1499.0, 1499.0});
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].channel, "bed");
  EXPECT_EQ(rows[1].channel, "x_nut");
  EXPECT_DOUBLE_EQ(rows[1].raw_c, 20.0 + 0.01 * 499);  // exact round trip of the double
  const auto fault = sink->QueryTemperatures({2000.0, 2000.0});
  ASSERT_EQ(fault.size(), 1u);
  EXPECT_TRUE(std::isnan(fault[0].raw_c));
  EXPECT_EQ(fault[0].status, "fault");

  // psql, knowing nothing of this code, sees the same rows and texts.
  EXPECT_EQ(server_->Psql("SELECT count(*) FROM machine_a.temperature"), "1001");
  EXPECT_EQ(server_->Psql("SELECT count(*) FROM machine_a.temperature WHERE raw_c IS NULL"), "1");
  EXPECT_EQ(server_->Psql("SELECT round(sum(correction_um)::numeric, 3) FROM machine_a.compensation"), "-155937.500");
  EXPECT_EQ(server_->Psql("SELECT message FROM machine_a.alarm"), "spike rejected: it's \"quoted\"\ttabbed\\ and on\ntwo lines");
  EXPECT_EQ(server_->Psql("SELECT value FROM machine_a.meta WHERE key = 'schema_version'"), std::to_string(HistoryDb::kSchemaVersion));
}

TEST_F(PostgresHistory, ReopeningKeepsDataAndNamesAndMachinesStaySeparate) {
  const std::vector<HistoryRecord> batch = {HistoryRecord::Temperature(1.0, "spindle", 30.0, 30.0, "ok")};
  Open("machine_b")->InsertBatch(batch);
  Open("machine_b")->InsertBatch(batch);  // a new connection finds the channel, migrates nothing
  Open("machine_c")->InsertBatch(batch);
  EXPECT_EQ(Open("machine_b")->Counts().temperature, 2);
  EXPECT_EQ(Open("machine_b")->Counts().channels, 1);
  EXPECT_EQ(Open("machine_c")->Counts().temperature, 1);
}

TEST_F(PostgresHistory, ABatchIsOneTransactionAllOrNothing) {
  auto sink = Open("machine_d");
  server_->Psql("ALTER TABLE machine_d.temperature ADD CONSTRAINT test_poison CHECK (status <> 'poison')");
  const std::vector<HistoryRecord> bad = {HistoryRecord::Temperature(1.0, "new_channel", 20.0, 20.0, "ok"),
                                          HistoryRecord::Compensation(1.0, "Y", 10.0, 1.5, "active"),
                                          HistoryRecord::Temperature(2.0, "new_channel", 20.0, 20.0, "poison")};
  EXPECT_THROW(sink->InsertBatch(bad), std::runtime_error);
  auto c = sink->Counts();
  EXPECT_EQ(c.temperature, 0);
  EXPECT_EQ(c.compensation, 0);
  EXPECT_EQ(c.channels, 0) << "the channel added inside the failed batch is rolled back too";
  // The same connection goes on; the channel rolled back is created again.
  const std::vector<HistoryRecord> good = {HistoryRecord::Temperature(3.0, "new_channel", 20.0, 20.0, "ok")};
  sink->InsertBatch(good);
  c = sink->Counts();
  EXPECT_EQ(c.temperature, 1);
  EXPECT_EQ(c.channels, 1);
}

TEST_F(PostgresHistory, RefusesASchemaOfAnotherApplicationAndANewerOne) {
  server_->Psql("CREATE SCHEMA erp; CREATE TABLE erp.orders(id int)");
  EXPECT_EQ(OpenError("erp"), "another application");
  EXPECT_EQ(server_->Psql("SELECT count(*) FROM information_schema.tables WHERE table_schema = 'erp'"), "1") << "nothing written";
  Open("future");
  server_->Psql("UPDATE future.meta SET value = '99' WHERE key = 'schema_version'");
  EXPECT_EQ(OpenError("future"), "newer trueaxis");
}

TEST_F(PostgresHistory, MigratesASchemaVersionOneHistory) {
  // A version-1 history as the first release made it: step 0 only, no schema_version row.
  server_->Psql("CREATE SCHEMA old1; SET search_path TO old1; " + PostgresHistorySink::MigrationSteps()[0]);
  EXPECT_EQ(server_->Psql("SELECT to_regclass('old1.calibration') IS NULL"), "t");
  auto sink = Open("old1");
  EXPECT_EQ(sink->schema_version(), HistoryDb::kSchemaVersion);
  EXPECT_EQ(server_->Psql("SELECT to_regclass('old1.calibration') IS NULL"), "f");
}

TEST_F(PostgresHistory, ServerGoneAndBackTheWriterCountsTheLossAndReconnects) {
  HistoryWriterOptions wo;
  wo.idle_wait_ms = 5;
  HistoryWriter writer(OpenHistorySink(server_->Url(), {"machine_e"}), wo);
  writer.PushTemperature(1.0, "x_nut", 20.0, 20.0, "ok");
  writer.Flush();
  EXPECT_EQ(writer.Stats().written, 1u);
  server_->Halt();
  writer.PushTemperature(2.0, "x_nut", 20.1, 20.1, "ok");
  writer.Flush();
  auto s = writer.Stats();
  EXPECT_EQ(s.failed, 1u) << s.BriefReport();
  EXPECT_FALSE(s.last_error.empty());
  ASSERT_TRUE(server_->Resume()) << server_->error();
  writer.PushTemperature(3.0, "x_nut", 20.2, 20.2, "ok");
  writer.Flush();
  s = writer.Stats();
  EXPECT_EQ(s.written, 2u) << s.BriefReport() << " " << s.last_error;
  writer.Close();
  EXPECT_EQ(server_->Psql("SELECT string_agg(time_s::text, ',' ORDER BY time_s) FROM machine_e.temperature"), "1,3");
}

TEST(OpenHistorySink, PostgresUrlOpensPostgresSinkPasswordNeverShown) {
  EnablePostgresHistory();
  try {
    OpenHistorySink("postgresql://shop:hunter2@127.0.0.1:1/shop?connect_timeout=2");  // nothing listens on port 1
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot connect to PostgreSQL"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("hunter2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("shop:***@"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trueaxis::store
