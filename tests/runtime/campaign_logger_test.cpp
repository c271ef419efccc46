// `campaign log`'s file side: the fit's layout, travelled paths from the CNC's counter or its
// positions, and a restart that goes on in the same file without losing or reordering rows.
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/station/campaign_logger.hpp"

namespace trueaxis::station {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

fs::path TempLog(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / (name + std::to_string(::getpid()) + ".csv");
  fs::remove(p);
  return p;
}

std::vector<hw::AxisState> Axes(double x_mm, double x_counter_mm, double y_mm) {
  std::vector<hw::AxisState> a(2);
  a[0].position_mm = x_mm;
  a[0].travel_mm = x_counter_mm;
  a[1].position_mm = y_mm;  // Y's CNC reports no counter: summed from positions
  return a;
}

TEST(CampaignLogger, WritesTheFitsLayoutAndGoesOnAfterARestart) {
  const fs::path path = TempLog("trueaxis_campaign_logger");
  hw::CncState cnc;
  std::vector<hw::RawTemperature> temps = {{21.5, false}, {0, true}};
  {
    CampaignLogger log(path.string(), {"X", "Y"}, {"x_nut", "ambient"});
    EXPECT_EQ(log.Header(), "time_s,date,coolant,x_mm,y_mm,x_travel_mm,y_travel_mm,t_x_nut_c,t_ambient_c\n");
    log.Poll(Axes(10, 1000, 5));
    log.Poll(Axes(30, 1020, 0));  // X +20 mm by its counter, Y 5 mm by position
    ASSERT_TRUE(log.Append(30, "2026-11-28T07:00:30", cnc, temps));
    log.Poll(Axes(30, 5, 10));  // the counter restarted (terminal restarted): 5 mm since
    cnc.coolant = CoolantState::kFlood;
    ASSERT_TRUE(log.Append(60, "2026-11-28T07:01:00", cnc, std::nullopt));
    EXPECT_FALSE(log.Append(60, "2026-11-28T07:01:00", cnc, temps)) << "not after the last row";
  }
  EXPECT_EQ(ReadTextFile(path.string()),
            "time_s,date,coolant,x_mm,y_mm,x_travel_mm,y_travel_mm,t_x_nut_c,t_ambient_c\n"
            "30,2026-11-28T07:00:30,off,30,0,20,5,21.5,\n"
            "60,2026-11-28T07:01:00,flood,30,10,25,15,,\n");
  {
    // A restart: the travels go on from the last row, rows only after it.
    CampaignLogger log(path.string(), {"X", "Y"}, {"x_nut", "ambient"});
    EXPECT_EQ(log.ResumedRows(), 2u);
    EXPECT_DOUBLE_EQ(log.LastTimeS(), 60);
    EXPECT_FALSE(log.Append(45, "d", cnc, temps));
    log.Poll(Axes(30, 200, 10));
    log.Poll(Axes(40, 210, 12));
    ASSERT_TRUE(log.Append(90, "2026-11-28T07:01:30", cnc, temps));
    EXPECT_EQ(log.TravelMm(), (std::vector<double>{35, 17}));
  }
  const auto read = measure::ReadTemperatureLog(path.string());  // as the fit reads it
  EXPECT_EQ(read.time_s, (std::vector<double>{30, 60, 90}));
  EXPECT_EQ(read.travel_mm.at("x"), (std::vector<double>{20, 25, 35}));
  EXPECT_EQ(read.coolant.back(), CoolantState::kFlood);
  fs::remove(path);
}

TEST(CampaignLogger, RefusesALogOfOtherChannels) {
  const fs::path path = TempLog("trueaxis_campaign_logger_other");
  { CampaignLogger log(path.string(), {"X"}, {"x_nut"}); }
  try {
    CampaignLogger log(path.string(), {"X"}, {"x_nut", "bed"});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(path.string()));
    EXPECT_THAT(e.what(), HasSubstr("not this machine's"));
  }
  fs::remove(path);
}

TEST(CampaignLogger, ARunConfigWithoutAModelIsReadForTheLog) {
  const std::string text = "[machine]\nkind = \"modbus\"\naxes = [\"X\"]\nchannels = [\"x_nut\"]\n";
  EXPECT_THROW(station::ParseSiteConfig(text, "c.toml"), InputError);
  const auto c = station::ParseSiteConfig(text, "c.toml", /*model_required=*/false);
  EXPECT_EQ(c.modbus.channel_names, std::vector<std::string>{"x_nut"});
  EXPECT_TRUE(c.installation.model_file.empty());
}

}  // namespace
}  // namespace trueaxis::station
