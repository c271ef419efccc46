#include "trueaxis/signal/offline_filter.hpp"

#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "support/shared_data.hpp"

#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::signal {
namespace {

const std::string kFlThermal = std::string(TRUEAXIS_SHARED_DATA_DIR) + "/fl_thermal/fl_thermal.csv";

TEST(ReadingsCsv, ParsesSelectsAndRejectsBadInput) {
  const auto t = ParseReadingsCsv("# rec\ntime_s,rpm,a,b\n0,0,20,21\n1,100,20.1,\n", "r.csv", {"a", "b"});
  EXPECT_EQ(t.channels, (std::vector<std::string>{"a", "b"}));
  ASSERT_EQ(t.time_s.size(), 2u);
  EXPECT_DOUBLE_EQ(t.values_c[0][1], 20.1);
  EXPECT_TRUE(std::isnan(t.values_c[1][1]));
  auto line_of = [](const std::string& text, const std::vector<std::string>& ch = {}) {
    try {
      ParseReadingsCsv(text, "r.csv", ch);
    } catch (const InputError& e) {
      return e.line();
    }
    return -1;
  };
  EXPECT_EQ(line_of("a,b\n1,2\n"), 1);                         // no time_s
  EXPECT_EQ(line_of("time_s,a\n0,1\nx,2\n"), 3);               // bad time
  EXPECT_EQ(line_of("time_s,a\n5,1\n4,2\n"), 3);               // time goes back
  EXPECT_EQ(line_of("time_s,a\n0,hot\n"), 2);                  // bad value
  EXPECT_EQ(line_of("time_s,a\n0,1,2\n"), 2);                  // field count
  EXPECT_EQ(line_of("time_s,a\n0,1\n", {"zz"}), 1);            // unknown channel
  EXPECT_THROW(ParseReadingsCsv("time_s,a\n", "r.csv"), InputError);
}

// docs/formats.md bounds every time to ±1e10 s, and a column needs a name (`calibrate` refuses the same).
TEST(ReadingsCsv, RefusesAnImplausibleTimeAndAnUnnamedColumn) {
  try {
    ParseReadingsCsv("time_s,a\n0,20\n7.2e12,20\n", "r.csv", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.field(), "time_s");
    EXPECT_NE(e.message().find("beyond"), std::string::npos) << e.message();
  }
  try {
    ParseReadingsCsv("time_s,a,\n0,20,21\n", "r.csv", {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 1);
    EXPECT_EQ(e.field(), "header");
  }
}

TEST(SignalCli, RefusesAHugeStartTimeAndWarnsOfAnUnmatchedCalibration) {
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_sigcli2_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string in = (dir / "r.csv").string(), db = (dir / "y.db").string(), cal = (dir / "cal.json").string();
  WriteTextFile(in, "time_s,a,b\n0,20,21\n1,20.1,21.1\n2,20.2,21.2\n");
  auto r = testing::RunCli("signal filter --in " + in + " --db " + db + " --start-time 1e300");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--start-time'"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(db));
  WriteTextFile(cal, R"({"format":"trueaxis-calibration","version":1,"reference":"ref","session":"s.csv",)"
                     R"("sensors":{"nope":{"gain":1.0,"offset_c":0.5,"points":3}}})");
  r = testing::RunCli("signal filter --in " + in + " --calibration " + cal);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: " + cal + ": sensor 'nope' is no channel of " + in), std::string::npos) << r.output;
  r = testing::RunCli("signal filter --in " + in + " --out " + in);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--out'"), std::string::npos) << r.output;
  EXPECT_EQ(ReadTextFile(in), "time_s,a,b\n0,20,21\n1,20.1,21.1\n2,20.2,21.2\n");
  std::filesystem::remove_all(dir);
}

// Real data nobody here produced (FL_THERMAL, 46 h, 16 temperatures at 15 s):
// a healthy recording must not be called faulty, and the filter must not
// distort it (its sensors are already smooth).
TEST(OfflineFilter, RealSpindleRecordingIsHealthy) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kFlThermal);
  std::vector<std::string> channels;
  for (int i = 1; i <= 16; ++i) channels.push_back("t" + std::to_string(i) + "_C");
  const auto table = ReadReadingsCsv(kFlThermal, channels);
  ASSERT_EQ(table.time_s.size(), 11115u);
  MonitorOptions o;
  const auto result = RunMonitorOffline(table, o);
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const auto& s = result.summary[c];
    EXPECT_EQ(s.samples, 11115u);
    EXPECT_EQ(s.samples_in_status[0], s.samples) << channels[c] << "\n" << result.FullReport();  // ok 100 %
    // The filter leaves smooth channels alone (rms change < 0.1 °C); t16 is
    // the noisy one, where it removes ~200 one-sample excursions.
    if (c != 15) EXPECT_LT(s.rms_raw_minus_filtered_c, 0.1) << channels[c] << "\n" << result.FullReport();
  }
  // t16 carries one-sample jumps of ~3 °C (26.86 -> 29.74 -> 28.16 at row 5232): the filter removes them.
  EXPECT_GT(result.summary[15].spikes_rejected, 100u);
  EXPECT_LT(result.summary[15].rms_raw_minus_filtered_c, 0.3);
  EXPECT_GT(result.summary[15].max_abs_raw_minus_filtered_c, 1.0);
  const std::string csv = FormatOfflineFilterCsv(table, result);
  EXPECT_EQ(csv.substr(0, csv.find(',', csv.find(',') + 1)), "time_s,t1_C_c");
}

TEST(OfflineFilter, InjectedFaultsAreReported) {
  ReadingsTable t;
  t.source = "synthetic";
  t.channels = {"a", "b"};
  t.values_c.assign(2, {});
  for (int i = 0; i < 2000; ++i) {
    t.time_s.push_back(i * 0.5);
    t.values_c[0].push_back(20 + 0.001 * i);
    t.values_c[1].push_back(i >= 1000 && i < 1100 ? 999.0 : 22.0 + 0.001 * i);  // open sensor for 50 s
  }
  const auto r = RunMonitorOffline(t, {});
  EXPECT_EQ(r.summary[0].samples_in_status[0], 2000u);
  EXPECT_GT(r.summary[1].samples_in_status[static_cast<int>(ChannelStatus::kOverRange)], 90u);
  EXPECT_EQ(r.summary[1].status_changes, 3u);  // no_data -> ok, ok -> over_range, over_range -> ok
  EXPECT_NE(r.FullReport().find("over_range"), std::string::npos);
}

TEST(SignalCli, FilterAndConvert) {
  TRUEAXIS_SKIP_WITHOUT_SHARED_FILE(kFlThermal);
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_sigcli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  auto r = testing::RunCli("signal filter --in " + kFlThermal + " --channels t1_C,t2_C,t3_C --groups 't1_C,t2_C,t3_C' --out " +
                           (dir / "f.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("11115 rows, 3 channels"), std::string::npos) << r.output;
  const std::string out = ReadTextFile((dir / "f.csv").string());
  EXPECT_EQ(out.substr(0, out.find('\n')), "time_s,t1_C_c,t1_C_status,t2_C_c,t2_C_status,t3_C_c,t3_C_status");
  r = testing::RunCli("signal filter --in " + kFlThermal + " --channels t1_C --median-window 4");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("median_window"), std::string::npos) << r.output;
  r = testing::RunCli("signal filter --in " + kFlThermal + " --channels t1_C --groups 't1_C,t99_C'");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCli("signal filter --in " + kFlThermal + " --channels nope");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("fl_thermal.csv:1: field 'nope'"), std::string::npos) << r.output;
  // Recorded data into the history database, then read back with `history query`.
  const std::string db = (dir / "fl.db").string();
  r = testing::RunCli("signal filter --in " + kFlThermal + " --channels t1_C,t9_C --db " + db +
                      " --start-time 2026-11-20T06:00:00Z");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("22230 readings stored"), std::string::npos) << r.output;
  r = testing::RunCli("history query --db " + db + " --channels t9_C --from 2026-11-20T06:00:00Z --to 2026-11-20T06:00:15Z");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("1795154400,2026-11-20T06:00:00.000Z,t9_C,33.1892103616527,33.1892103616527,ok"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("2026-11-20T06:00:15.000Z,t9_C,33.1793069856068,"), std::string::npos) << r.output;
  r = testing::RunCli("signal filter --in " + kFlThermal + " --channels t1_C --db " + db + " --start-time noon");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCli("signal convert --adc 2048");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("25.0061 °C (ok)"), std::string::npos) << r.output;
  r = testing::RunCli("signal convert --adc 4095");
  EXPECT_NE(r.output.find("at_adc_rail"), std::string::npos) << r.output;
  r = testing::RunCli("signal convert --ds18b20 0x0550");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("85.0000 °C (suspicious)"), std::string::npos) << r.output;
  r = testing::RunCli("signal convert --ds18b20 0x1FFFF");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = testing::RunCli("signal convert --adc 5 --ds18b20 0x0001");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::signal
