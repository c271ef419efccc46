// `campaign plan`: the schedule is the virtual campaign's, the folder skeleton is what `campaign
// log/add/check` and the fit read, and the real-machine file refuses what would make a wrong plan.
#include "trueaxis/campaign/campaign_folder.hpp"
#include "trueaxis/campaign/campaign_plan.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::campaign {
namespace {

namespace fs = std::filesystem;
const std::string kSource = TRUEAXIS_SOURCE_DIR;

fs::path TempDir(const std::string& name) {
  fs::path p = fs::temp_directory_path() / ("trueaxis_campaign_plan_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(p);
  return p;
}

TEST(CampaignPlan, ScheduleFollowsTheVirtualCampaign) {
  const auto machine = ReadCampaignMachineFile(kSource + "/examples/machines/vmc850.toml");
  EXPECT_TRUE(machine.virtual_machine_file);
  PlanOptions o;
  const auto plan = MakeCampaignPlan(machine, o);
  ASSERT_EQ(plan.axes, (std::vector<std::string>{"X", "Y", "Z"}));
  EXPECT_EQ(plan.controllers.size(), 4u);  // a virtual machine file names no controller
  std::vector<std::string> seq;
  for (const auto& s : plan.steps) seq.push_back(std::to_string(s.day) + " " + s.axis + " " + s.state);
  // Days 0–2: each axis cold, warm, cooldown; 3–5: the first coolant visit.
  const std::vector<std::string> head = {"0 X cold", "0 X warm", "0 X cooldown", "1 Y cold", "1 Y warm", "1 Y cooldown",
                                         "2 Z cold", "2 Z warm", "2 Z cooldown", "3 X coolant", "3 X coolant_rest",
                                         "4 Y coolant", "4 Y coolant_rest", "5 Z coolant", "5 Z coolant_rest"};
  ASSERT_GT(seq.size(), head.size());
  EXPECT_EQ(std::vector<std::string>(seq.begin(), seq.begin() + static_cast<long>(head.size())), head);
  // Then days 60 and 150 at 03:00, 10:00, 19:00 for each axis, then the second coolant visit.
  int ambient = 0;
  for (const auto& s : plan.steps)
    if (s.state == "ambient") {
      ++ambient;
      EXPECT_TRUE(s.day == 60 || s.day == 150);
      EXPECT_TRUE(s.hour == 3 || s.hour == 10 || s.hour == 19);
      EXPECT_EQ(s.runs, 5);
    }
  EXPECT_EQ(ambient, 2 * 3 * 3);
  EXPECT_EQ(seq.back(), "153 Z coolant_rest");
  for (const auto& s : plan.steps)
    if (s.state == "warm") EXPECT_EQ(s.max_tests, sim::CampaignOptions{}.max_warm_measurements);

  // A dry machine, one visit, one axis.
  o.schedule.coolant_session = false;
  o.axes = {"y"};
  const auto dry = MakeCampaignPlan(machine, o);
  EXPECT_EQ(dry.axes, std::vector<std::string>{"Y"});
  for (const auto& s : dry.steps) EXPECT_TRUE(s.state.rfind("coolant", 0) != 0) << s.state;
  o.axes = {"Q"};
  EXPECT_THROW(MakeCampaignPlan(machine, o), InputError);
}

TEST(CampaignPlan, WritesTheFolderTheOtherCommandsFill) {
  const auto machine = ReadCampaignMachineFile(kSource + "/examples/campaign/vmc850_fanuc.toml");
  ASSERT_TRUE(machine.controller);
  EXPECT_EQ(*machine.controller, Controller::kFanuc);
  PlanOptions o;
  o.out_dir = TempDir("folder").string();
  o.start_date = "2026-03-02";
  const auto plan = MakeCampaignPlan(machine, o);
  const auto files = WriteCampaignFolder(plan);
  const fs::path dir(o.out_dir);
  const auto manifest = measure::ReadCampaignManifest((dir / "manifest.json").string());
  EXPECT_EQ(manifest.format, "trueaxis-campaign");
  EXPECT_TRUE(manifest.measurements.empty());
  EXPECT_EQ(manifest.axes, plan.axes);
  EXPECT_EQ(manifest.machine, "VMC-850 #3");
  EXPECT_EQ(manifest.SensorsAt("ambient"), std::vector<std::string>{"room"});
  EXPECT_EQ(manifest.NutSensor("X"), "x_nut");
  EXPECT_EQ(manifest.LocationOf("x_column"), "x_structure");
  // The log: the header only, with every sensor's column.
  const auto log = measure::ReadTemperatureLog((dir / "temperature_log.csv").string(), true);
  EXPECT_EQ(log.sensors, manifest.sensors);
  EXPECT_TRUE(log.time_s.empty());
  EXPECT_EQ(log.travel_mm.size(), 3u);
  // FANUC programs only: per axis the 5-run and the 3-run test, and the warm-up.
  int programs = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "programs")) programs += e.is_regular_file();
  EXPECT_EQ(programs, 7);
  EXPECT_TRUE(fs::exists(dir / "programs/fanuc/O7001_X_laser5_fanuc.nc"));
  EXPECT_TRUE(fs::exists(dir / "programs/fanuc/O7002_X_laser3_fanuc.nc"));
  EXPECT_TRUE(fs::exists(dir / "programs/fanuc/O7900_warmup_fanuc.nc"));
  // plan.md: the targets as listed, the dates, the rule's numbers.
  const std::string md = ReadTextFile((dir / "plan.md").string());
  EXPECT_NE(md.find(fmt::format("{:.3f}", plan.targets[0].targets_mm[1])), std::string::npos);
  EXPECT_NE(md.find("| 2026-03-02 | 07:00 | X | cold |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 2026-05-01 | 03:00 | X | ambient |"), std::string::npos);  // day 60
  EXPECT_NE(md.find("0.5 °C"), std::string::npos);
  EXPECT_NE(std::find(files.begin(), files.end(), "plan.json"), files.end());
  // The machine file's CTE reaches plan.json, where `campaign add` stamps it on the files.
  EXPECT_DOUBLE_EQ(machine.axes[0].cte_um_per_m_c, 11.5);
  const auto planned = OpenCampaignFolder(o.out_dir).PlannedCteUmPerMC("X");
  ASSERT_TRUE(planned);
  EXPECT_DOUBLE_EQ(*planned, 11.5);
  EXPECT_FALSE(OpenCampaignFolder(o.out_dir).PlannedCteUmPerMC("B"));
  // A campaign is never overwritten.
  EXPECT_THROW(WriteCampaignFolder(plan), InputError);
  fs::remove_all(dir);
}

void ExpectRefused(const std::string& toml, const std::string& field, const std::string& says) {
  try {
    ParseCampaignMachineToml(toml, "m.toml");
    FAIL() << "accepted:\n" << toml;
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
  }
}

TEST(CampaignMachine, RefusesWhatWouldMakeAWrongPlan) {
  const std::string head = "[machine]\ncontroller = \"linuxcnc\"\n";
  const std::string axis = "[[axis]]\nname = \"X\"\ntravel_mm = 500\nlead_mm = 10\n";
  const std::string sensors = "[[sensor]]\nname = \"x_nut\"\n[[sensor]]\nname = \"room\"\nlocation = \"ambient\"\n";
  EXPECT_NO_THROW(ParseCampaignMachineToml(head + axis + sensors, "m.toml"));
  ExpectRefused(head + axis + "[[sensor]]\nname = \"room\"\nlocation = \"ambient\"\n", "sensor", "x_nut");
  ExpectRefused(head + axis + "[[sensor]]\nname = \"x_nut\"\n", "sensor", "ambient");
  ExpectRefused(head + axis + "travl_mm = 3\n" + sensors, "axis[0].travl_mm", "unknown");
  ExpectRefused(head + axis + "min_mm = -500\nmax_mm = 0\n" + sensors, "axis[0].travel_mm", "not both");
  ExpectRefused("[machine]\ncontroller = \"mazak\"\n" + axis + sensors, "machine.controller", "mazak");
  ExpectRefused(head + axis + sensors + "[[sensor]]\nname = \"x_head\"\nlocation = \"x_head\"\n", "sensor[2].location",
                "unknown location");
  ExpectRefused(head + axis + "cte_um_per_m_c = 11500\n" + sensors, "axis[0].cte_um_per_m_c", "");
  EXPECT_TRUE(std::isnan(ParseCampaignMachineToml(head + axis + sensors, "m.toml").axes[0].cte_um_per_m_c));
  // Machine coordinates: negative limits are kept, the reference defaults to the fixed end.
  const auto m = ParseCampaignMachineToml(
      head + "[[axis]]\nname = \"x\"\nmin_mm = -850\nmax_mm = 0\nlead_mm = 12\nfixed_end = \"max\"\n" + sensors, "m.toml");
  EXPECT_EQ(m.axes[0].name, "X");
  EXPECT_EQ(m.axes[0].min_mm, -850);
  EXPECT_EQ(m.axes[0].reference_mm, 0);
  EXPECT_FALSE(m.axes[0].fixed_at_min);
}

}  // namespace
}  // namespace trueaxis::campaign
