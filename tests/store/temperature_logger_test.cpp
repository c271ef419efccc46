#include "trueaxis/store/temperature_logger.hpp"

#include <algorithm>

#include <gtest/gtest.h>

#include "test_dir.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::testing {
long ThreadAllocationCount();
}

namespace trueaxis::store {
namespace {

using TemperatureLoggerTest = testing::TempDirTest;
using signal::ChannelStatus;

TEST_F(TemperatureLoggerTest, DecimatesReadingsLogsStatusChangesAndAllocatesNothing) {
  signal::TemperatureMonitor monitor({"ambient", "x_nut"});
  std::vector<hw::RawTemperature> raw(2);
  long allocations = 0;
  {
    HistoryWriter writer(Path("h.db"));
    TemperatureLogger logger(writer, monitor, {.log_period_s = 1.0});
    double t = 0;
    const long before = testing::ThreadAllocationCount();
    for (int i = 0; i < 1000; ++i, t += 0.1) {  // 100 s at 10 Hz
      raw[0] = {20.0, false};
      raw[1] = (i >= 400 && i < 450) ? hw::RawTemperature{0.0, true} : hw::RawTemperature{25.0, false};
      monitor.Update(t, raw);
      logger.Log(t);
    }
    allocations = testing::ThreadAllocationCount() - before;
    writer.Flush();
    EXPECT_EQ(writer.Stats().dropped, 0u);
    EXPECT_EQ(logger.alarms_pushed(), 4u);
  }
  EXPECT_EQ(allocations, 0);
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  const auto ambient = db.QueryTemperatures({}, {"ambient"});
  EXPECT_EQ(ambient.size(), 100u);  // once per second
  const auto nut = db.QueryTemperatures({}, {"x_nut"});
  const auto alarms = db.QueryAlarms({});
  ASSERT_EQ(alarms.size(), 4u);
  // A row at the very instant of each status change, whatever the period.
  for (int k : {2, 3}) {
    const bool found = std::any_of(nut.begin(), nut.end(), [&](const TemperatureRow& r) {
      return r.time_s == alarms[k].time_s && r.status == (k == 2 ? "hardware_fault" : "ok");
    });
    EXPECT_TRUE(found) << k;
  }
  EXPECT_GT(nut.size(), 100u);
  // Start (no_data -> ok) for both channels, then the fault and its clearing on x_nut.
  ASSERT_EQ(alarms.size(), 4u);
  EXPECT_EQ(alarms[2].severity, "fault");
  EXPECT_EQ(alarms[2].source, "x_nut");
  EXPECT_NE(alarms[2].message.find("x_nut -> hardware_fault"), std::string::npos) << alarms[2].message;
  EXPECT_EQ(alarms[3].severity, "info");
  EXPECT_NE(alarms[3].message.find("-> ok"), std::string::npos);
  EXPECT_GT(alarms[3].time_s, alarms[2].time_s);
}

TEST_F(TemperatureLoggerTest, PeriodZeroLogsEveryReading) {
  signal::TemperatureMonitor monitor({"a"});
  std::vector<hw::RawTemperature> raw = {{21.0, false}};
  {
    HistoryWriter writer(Path("h.db"));
    TemperatureLogger logger(writer, monitor, {.log_period_s = 0, .alarms_on_status_change = false});
    for (int i = 0; i < 250; ++i) {
      monitor.Update(i * 0.01, raw);
      logger.Log(i * 0.01);
    }
    EXPECT_EQ(logger.readings_pushed(), 250u);
    EXPECT_EQ(logger.alarms_pushed(), 0u);
  }
  HistoryDb db(Path("h.db"), HistoryDb::Mode::kReadOnly);
  EXPECT_EQ(db.QueryTemperatures({}).size(), 250u);
  EXPECT_TRUE(db.QueryAlarms({}).empty());
}

}  // namespace
}  // namespace trueaxis::store
