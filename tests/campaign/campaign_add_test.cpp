// `campaign add`: a laser file put on the campaign clock with the logged temperatures at each of
// its points, written into the folder and listed in manifest.json as the fit reads it.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_file.hpp"
#include "trueaxis/campaign/campaign_add.hpp"
#include "trueaxis/campaign/campaign_clock.hpp"
#include "trueaxis/modelfit/fit_input.hpp"

namespace trueaxis::campaign {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr const char* kStart = "2026-11-28T07:00:00";

// A campaign started at kStart whose log reads x_nut = 20 + t/360 (°C, t campaign seconds) every
// 30 s from 0 to `last_s`, X travelling 10 mm a row, coolant `coolant`.
fs::path Campaign(const std::string& name, int last_s, const std::string& coolant = "off") {
  const fs::path dir = fs::temp_directory_path() / (name + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  WriteTextFile((dir / "manifest.json").string(),
                fmt::format(R"({{"format": "trueaxis-sim-campaign", "version": 1, "start_date": "{}",
                    "sensors": ["x_nut", "ambient"], "temperature_log": "temperature_log.csv", "measurements": []}})",
                            kStart));
  std::string log = "time_s,date,coolant,x_mm,x_travel_mm,t_x_nut_c,t_ambient_c\n";
  for (int t = 0; t <= last_s; t += 30)
    log += fmt::format("{},d,{},100,{},{},{}\n", t, coolant, t / 3, 20 + t / 360.0, t == 300 ? "" : "19.5");
  WriteTextFile((dir / "temperature_log.csv").string(), log);
  return dir;
}

// A laser file as laser software writes it: 2 runs × 2 targets × both directions, a point every
// 20 s from 0 to 140 s, no machine sensors; `date` its start ("" for none).
fs::path LaserFile(const fs::path& dir, const std::string& name, const std::string& date, double offset_um = 0) {
  std::string text = "# axis: X\n";
  if (!date.empty()) text += "# date: " + date + "\n";
  text += "run,direction,target_mm,deviation_um,time_s\n";
  int k = 0;
  for (int run = 1; run <= 2; ++run)
    for (const char* d : {"+", "-"})
      for (int target : {0, 100}) {
        text += fmt::format("{},{},{},{},{}\n", run, d, target, target * 0.05 + offset_um, 20 * k);
        ++k;
      }
  const fs::path p = dir / ".." / (dir.filename().string() + "_" + name);
  WriteTextFile(p.string(), text);
  return p;
}

CampaignAddOptions Add(const fs::path& dir, const fs::path& file, const std::string& state) {
  CampaignAddOptions o;
  o.campaign_dir = dir.string();
  o.file = file.string();
  o.axis = "X";
  o.state = state;
  return o;
}

TEST(CampaignAdd, StampsTheFileOnTheCampaignClockWithTheLoggedTemperatures) {
  const fs::path dir = Campaign("trueaxis_add_stamp", 3600);
  const auto r = AddToCampaign(Add(dir, LaserFile(dir, "cold.csv", "2026-11-28T07:10:00"), "cold"));
  EXPECT_THAT(r.start_source, HasSubstr("the file's date"));
  EXPECT_DOUBLE_EQ(r.start_time_s, 600);
  EXPECT_DOUBLE_EQ(r.end_time_s, 740);
  EXPECT_EQ(fs::path(r.written).filename(), "X_01_cold.csv");
  const auto m = measure::ReadMeasurementFile(r.written);
  ASSERT_EQ(m.sensor_names, (std::vector<std::string>{"x_nut", "ambient"}));
  for (const auto& p : m.points) {
    // Linear between the rows around the point's time: the log's nut at 600 + time_s.
    EXPECT_NEAR(p.temperatures_c[0], 20 + (600 + *p.time_s) / 360.0, 1e-9) << *p.time_s;
  }
  EXPECT_EQ(m.Meta("campaign_time_s"), "600");
  EXPECT_EQ(m.Meta("state"), "cold");
  const auto manifest = nlohmann::json::parse(ReadTextFile((dir / "manifest.json").string()));
  ASSERT_EQ(manifest["measurements"].size(), 1u);
  const auto& e = manifest["measurements"][0];
  EXPECT_EQ(e["file"], "X_01_cold.csv");
  EXPECT_EQ(e["state"], "cold");
  EXPECT_EQ(e["coolant"], "off");
  EXPECT_EQ(e["start_time_s"], 600);
  // The fit reads it, the log's history behind it.
  const auto states = model::LoadFitStates({}, (dir / "manifest.json").string());
  ASSERT_EQ(states.size(), 1u);
  EXPECT_EQ(states[0].kind, model::StateKind::kCold);
  EXPECT_FALSE(states[0].history.empty());
  EXPECT_TRUE(states[0].history.HasTravel());
}

// The machine file's CTE (via the plan) is stamped on each file for the fit's ρ, unless the laser
// file gives its own; without a plan nothing is invented.
TEST(CampaignAdd, StampsThePlannedCteUnlessTheFileHasOne) {
  const fs::path dir = Campaign("trueaxis_add_cte", 3600);
  const auto none = AddToCampaign(Add(dir, LaserFile(dir, "cold.csv", "2026-11-28T07:10:00"), "cold"));
  EXPECT_FALSE(measure::ReadMeasurementFile(none.written).Meta("cte_um_per_m_c"));
  WriteTextFile((dir / "plan.json").string(),
                R"({"format": "trueaxis-campaign-plan", "axes": [{"axis": "Y", "cte_um_per_m_c": 8},
                    {"axis": "X", "cte_um_per_m_c": 11.5}]})");
  const auto planned = AddToCampaign(Add(dir, LaserFile(dir, "warm.csv", "2026-11-28T07:20:00"), "warm"));
  EXPECT_EQ(measure::ReadMeasurementFile(planned.written).Meta("cte_um_per_m_c"), "11.5");
  fs::path own = LaserFile(dir, "warm2.csv", "2026-11-28T07:30:00");
  WriteTextFile(own.string(), "# cte_um_per_m_c: 2.5\n" + ReadTextFile(own.string()));
  const auto kept = AddToCampaign(Add(dir, own, "warm"));
  EXPECT_EQ(measure::ReadMeasurementFile(kept.written).Meta("cte_um_per_m_c"), "2.5");
  WriteTextFile((dir / "plan.json").string(), R"({"axes": [{"axis": "X", "cte_um_per_m_c": "steel"}]})");
  try {
    AddToCampaign(Add(dir, LaserFile(dir, "warm3.csv", "2026-11-28T07:40:00"), "warm"));
    ADD_FAILURE() << "a CTE that is not a number was taken";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("plan.json"));
    EXPECT_THAT(e.what(), HasSubstr("cte_um_per_m_c"));
  }
}

TEST(CampaignAdd, AnEmptyLogCellStaysEmptyAndWarmTestsCountTheirRise) {
  const fs::path dir = Campaign("trueaxis_add_warm", 3600);
  AddToCampaign(Add(dir, LaserFile(dir, "a.csv", "2026-11-28T07:00:00"), "cold"));
  // --start overrides the file's date; the ambient cell at 300 s is empty in the log.
  auto o = Add(dir, LaserFile(dir, "b.csv", "2026-11-28T09:00:00", 3), "warm");
  o.start = "2026-11-28T07:04:00";
  const auto r = AddToCampaign(o);
  EXPECT_EQ(r.start_source, "--start");
  EXPECT_DOUBLE_EQ(r.start_time_s, 240);
  EXPECT_EQ(fs::path(r.written).filename(), "X_02_warm_01.csv");
  // Mean nut of the cold test (0–140 s) vs this one (240–380 s): 240 s / 360 s/°C later.
  EXPECT_NEAR(r.nut_rise_c, 240 / 360.0, 1e-3);  // the cold mean as the manifest keeps it (0.001 °C)
  const auto m = measure::ReadMeasurementFile(r.written);
  int empty = 0;
  for (const auto& p : m.points) empty += std::isnan(p.temperatures_c[1]) && 240 + *p.time_s > 270 && 240 + *p.time_s < 330;
  EXPECT_GT(empty, 0) << "a point between the rows around the flagged reading has no ambient";
  // --end: the file's last point ends then.
  auto e = Add(dir, LaserFile(dir, "c.csv", ""), "warm");
  e.end = "2026-11-28T07:30:00";
  const auto re = AddToCampaign(e);
  EXPECT_DOUBLE_EQ(re.start_time_s, 1800 - 140);
  EXPECT_EQ(re.sequence, 2);
}

TEST(CampaignAdd, RefusesATestTheLogDoesNotCoverNamingFileAndTimes) {
  const fs::path dir = Campaign("trueaxis_add_cover", 1200);
  const fs::path late = LaserFile(dir, "late.csv", "2026-11-28T07:19:00");
  try {
    AddToCampaign(Add(dir, late, "cold"));
    FAIL() << "accepted a test past the log's end";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr(late.string()));
    EXPECT_THAT(e.what(), HasSubstr("1140–1280 s"));
    EXPECT_THAT(e.what(), HasSubstr("temperature_log.csv"));
  }
  const auto manifest = nlohmann::json::parse(ReadTextFile((dir / "manifest.json").string()));
  EXPECT_TRUE(manifest["measurements"].empty()) << "nothing half-added";
  // No date in the file and no option: the modification time, taken as the test's end (now: past the log).
  EXPECT_THROW(AddToCampaign(Add(dir, LaserFile(dir, "undated.csv", ""), "cold")), InputError);
  // A coolant state over a log that reads coolant off needs the coolant named.
  EXPECT_THROW(AddToCampaign(Add(dir, LaserFile(dir, "c.csv", "2026-11-28T07:01:00"), "coolant")), InputError);
  auto c = Add(dir, LaserFile(dir, "c2.csv", "2026-11-28T07:01:00"), "coolant");
  c.coolant = "flood";
  EXPECT_NO_THROW(AddToCampaign(c));
}

TEST(CampaignClock, ReadsLocalDatesZonesAndFractions) {
  const auto local = ParseCampaignDate("2026-11-28T07:00:00");
  ASSERT_TRUE(local);
  EXPECT_EQ(FormatCampaignDate(*local), "2026-11-28T07:00:00");
  EXPECT_DOUBLE_EQ(*ParseCampaignDate("2026-11-28 07:00:01.25"), *local + 1.25);
  EXPECT_DOUBLE_EQ(*ParseCampaignDate("2026-11-28T07:00:00Z") - *ParseCampaignDate("2026-11-28T08:00:00+01:00"), 0);
  EXPECT_FALSE(ParseCampaignDate("28.11.2026 07:00"));
  EXPECT_FALSE(ParseCampaignDate("2026-11-28"));
}

}  // namespace
}  // namespace trueaxis::campaign
