// `campaign check` on a virtual campaign (sim campaign's folder, read as it is) and on the same
// folder with states, files and log rows taken away: what is covered, what is missing, the file
// problems — and the plan's states are the ones the virtual campaign measured.
#include "trueaxis/campaign/campaign_check.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "trueaxis/campaign/campaign_plan.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/sim/campaign.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::campaign {
namespace {

namespace fs = std::filesystem;
const std::string kMachine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc400_small.toml";

class CampaignCheckTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base_ = fs::temp_directory_path() / ("trueaxis_campaign_check_" + std::to_string(::getpid()));
    fs::remove_all(base_);
    sim::CampaignOptions o;
    o.out_dir = (base_ / "sim").string();
    o.axes = {"X"};
    summary_ = sim::RunCampaign(sim::ReadMachineFile(kMachine), o);
  }
  static void TearDownTestSuite() { fs::remove_all(base_); }

  // A copy of the virtual campaign to take things away from.
  static fs::path Copy(const std::string& name) {
    const fs::path to = base_ / name;
    fs::remove_all(to);
    fs::copy(base_ / "sim", to, fs::copy_options::recursive);
    return to;
  }
  static const AxisCoverage& X(const CampaignCheckResult& r) {
    for (const auto& a : r.axes)
      if (a.axis == "X") return a;
    throw std::runtime_error("no axis X");
  }
  static bool Says(const std::vector<std::string>& lines, const std::string& what) {
    for (const auto& l : lines)
      if (l.find(what) != std::string::npos) return true;
    return false;
  }

  static inline fs::path base_;
  static inline sim::CampaignSummary summary_;
};

TEST_F(CampaignCheckTest, VirtualCampaignCoversEveryState) {
  const auto r = CheckCampaign((base_ / "sim").string(), CheckOptions{});
  EXPECT_EQ(r.manifest.format, "trueaxis-campaign");
  EXPECT_TRUE(r.file_problems.empty()) << CheckReport(r);
  ASSERT_EQ(r.axes.size(), 1u);
  const auto& x = X(r);
  std::map<std::string, int> expected;
  for (const auto& f : summary_.files) ++expected[f.state];
  EXPECT_EQ(x.tests, expected);
  EXPECT_EQ(x.saturation, 1) << CheckReport(r);  // the virtual warm-up's last test is at saturation
  double max_rise = 0;
  for (const auto& f : summary_.files)
    if (f.state == "warm") max_rise = std::max(max_rise, f.nut_rise_c);
  EXPECT_NEAR(x.max_nut_rise_c, max_rise, 0.002);
  EXPECT_EQ(x.ambient_days, (std::set<int>{60, 150}));
  EXPECT_EQ(x.coolants, std::set<std::string>{"flood"});
  EXPECT_FALSE(Says(x.missing, "no cold test"));
  EXPECT_FALSE(Says(x.missing, "no cool-down"));
  EXPECT_FALSE(Says(x.missing, "another day"));
  EXPECT_FALSE(Says(x.missing, "no coolant"));
  // The room range is the range of the ambient sensor over the tests.
  ASSERT_TRUE(std::isfinite(x.room_min_c));
  double lo = 1e9, hi = -1e9;
  for (const auto& e : r.manifest.measurements) {
    const double v = e.MeanTemperatureC("ambient");
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  EXPECT_DOUBLE_EQ(x.room_min_c, lo);
  EXPECT_DOUBLE_EQ(x.room_max_c, hi);
  // A workshop range inside the measured one: nothing to add; one beyond it: the warm afternoon.
  CheckOptions inside;
  inside.room_low_c = lo + 0.1;
  inside.room_high_c = hi - 0.1;
  EXPECT_FALSE(Says(X(CheckCampaign((base_ / "sim").string(), inside)).missing, "room above"));
  CheckOptions beyond;
  beyond.room_high_c = hi + 2;
  const auto warm = X(CheckCampaign((base_ / "sim").string(), beyond));
  EXPECT_TRUE(Says(warm.missing, fmt::format("no measurement with the room above {:.1f} °C", hi)));
  EXPECT_TRUE(Says(warm.missing, "measure one warm afternoon"));
}

TEST_F(CampaignCheckTest, PlanNamesTheStatesTheVirtualCampaignMeasured) {
  PlanOptions o;
  o.axes = {"X"};
  const auto plan = MakeCampaignPlan(ReadCampaignMachineFile(kMachine), o);
  std::vector<std::string> planned, measured;
  for (const auto& s : plan.steps)
    if (planned.empty() || planned.back() != s.state) planned.push_back(s.state);
  for (const auto& f : summary_.files)
    if (measured.empty() || measured.back() != f.state) measured.push_back(f.state);
  // The same order; a cool-down the machine never gives (the nut under coolant falls less than the
  // step within the time allowed) is planned but not measured: the measured states are the planned
  // ones with at most such steps left out.
  std::size_t p = 0;
  for (const auto& state : measured) {
    while (p < planned.size() && planned[p] != state) {
      EXPECT_TRUE(planned[p] == "coolant_rest" || planned[p] == "cooldown") << "planned but skipped: " << planned[p];
      ++p;
    }
    ASSERT_LT(p, planned.size()) << "measured but not planned: " << state;
    ++p;
  }
  EXPECT_EQ(planned.front(), "cold");
  EXPECT_EQ(std::set<std::string>(measured.begin(), measured.end()),
            (std::set<std::string>{"cold", "warm", "cooldown", "ambient", "coolant"}));
}

TEST_F(CampaignCheckTest, MissingStatesAreSaid) {
  const fs::path dir = Copy("cold_warm_only");
  auto m = measure::ReadCampaignManifest((dir / "manifest.json").string());
  std::vector<measure::CampaignEntry> kept;
  for (const auto& e : m.measurements)
    if (e.state == "cold" || e.state == "warm") kept.push_back(e);
  m.measurements = kept;
  measure::WriteCampaignManifest(m, (dir / "manifest.json").string());
  const auto r = CheckCampaign(dir.string(), CheckOptions{});
  EXPECT_TRUE(r.file_problems.empty());
  const auto& x = X(r);
  EXPECT_TRUE(Says(x.missing, "no cool-down test"));
  EXPECT_TRUE(Says(x.missing, "no test on another day"));
  EXPECT_TRUE(Says(x.missing, "no coolant test"));
  EXPECT_FALSE(Says(x.missing, "no cold test"));
  EXPECT_FALSE(r.Complete());

  // Only the first two warm-up tests: too few; the log holds no 30 min of warm-up before the
  // second, so saturation is unknown, said as such.
  const auto first_warm = [&](int n) {
    std::vector<measure::CampaignEntry> out;
    for (const auto& e : kept)
      if (e.state == "cold" || (e.state == "warm" && e.sequence <= n)) out.push_back(e);
    return out;
  };
  m.measurements = first_warm(2);
  measure::WriteCampaignManifest(m, (dir / "manifest.json").string());
  const auto two = CheckCampaign(dir.string(), CheckOptions{});
  EXPECT_TRUE(Says(X(two).missing, "only 2 warm-up test(s)"));
  EXPECT_EQ(X(two).saturation, -1);
  EXPECT_NE(CheckReport(two).find("saturation unknown"), std::string::npos);
  // The first four: the nut still rising fast before the last of them.
  m.measurements = first_warm(4);
  measure::WriteCampaignManifest(m, (dir / "manifest.json").string());
  const AxisCoverage e = X(CheckCampaign(dir.string(), CheckOptions{}));
  EXPECT_FALSE(Says(e.missing, "warm-up test(s)"));
  EXPECT_EQ(e.saturation, 0);
  EXPECT_GT(e.rise_before_last_warm_c, 3 * CheckOptions{}.rules.saturation_rise_c);
  EXPECT_TRUE(Says(e.missing, "stopped before saturation"));

  // No cold test.
  m.measurements = {first_warm(4).back()};
  measure::WriteCampaignManifest(m, (dir / "manifest.json").string());
  EXPECT_TRUE(Says(X(CheckCampaign(dir.string(), CheckOptions{})).missing, "no cold test"));
}

// The virtual campaign's files carry the screw's CTE: the room's soak holds beyond the measured
// room range. Without it the check asks for it, as the fit would extrapolate a fitted ρ.
TEST_F(CampaignCheckTest, AMissingCteIsSaidWithWhatItCosts) {
  const fs::path dir = Copy("no_cte");
  const auto with = CheckCampaign(dir.string(), CheckOptions{});
  EXPECT_DOUBLE_EQ(X(with).cte_um_per_m_c, 11.5);
  EXPECT_FALSE(Says(X(with).missing, "no CTE"));
  EXPECT_NE(CheckReport(with).find("the room's soak still holds"), std::string::npos) << CheckReport(with);
  const auto m = measure::ReadCampaignManifest((dir / "manifest.json").string());
  for (const auto& e : m.measurements) {
    const fs::path p = dir / e.file;
    std::string text = ReadTextFile(p.string()), out;
    for (std::size_t at = 0; at < text.size();) {
      const std::size_t end = std::min(text.find('\n', at), text.size());
      const std::string line = text.substr(at, end - at);
      if (line.rfind("# cte_um_per_m_c", 0) != 0) out += line + "\n";
      at = end + 1;
    }
    WriteTextFile(p.string(), out);
  }
  const auto without = CheckCampaign(dir.string(), CheckOptions{});
  EXPECT_TRUE(std::isnan(X(without).cte_um_per_m_c));
  EXPECT_TRUE(Says(X(without).missing, "no CTE of the axis's feedback"));
  EXPECT_NE(CheckReport(without).find("outside, it extrapolates"), std::string::npos) << CheckReport(without);
}

TEST_F(CampaignCheckTest, FileProblemsAreNamed) {
  const fs::path dir = Copy("problems");
  auto m = measure::ReadCampaignManifest((dir / "manifest.json").string());
  ASSERT_GE(m.measurements.size(), 4u);
  fs::remove(dir / m.measurements[1].file);                     // a listed file gone
  m.measurements[2].start_time_s = m.measurements.back().end_time_s + 30 * 86400.0;  // long after the log ends
  m.measurements[2].end_time_s = m.measurements[2].start_time_s + 600;
  m.measurements[3].start_time_s = std::nan("");                 // never stamped
  measure::WriteCampaignManifest(m, (dir / "manifest.json").string());
  const auto r = CheckCampaign(dir.string(), CheckOptions{});
  ASSERT_EQ(r.file_problems.size(), 3u) << CheckReport(r);
  EXPECT_NE(r.file_problems[0].find(m.measurements[1].file + ": the file is missing"), std::string::npos);
  EXPECT_NE(r.file_problems[1].find("no temperatures in the log at its time"), std::string::npos) << r.file_problems[1];
  EXPECT_NE(r.file_problems[2].find("no start_time_s"), std::string::npos);
}

TEST_F(CampaignCheckTest, NutColumnEmptyAtATestIsAProblem) {
  const fs::path dir = Copy("nut_unplugged");
  const auto m = measure::ReadCampaignManifest((dir / "manifest.json").string());
  const auto& cold = m.measurements.front();
  // Blank the x_nut column over the cold test (the channel flagged by its module).
  const std::string path = (dir / "temperature_log.csv").string();
  std::string text = ReadTextFile(path), out;
  std::size_t col = 0;
  std::istringstream in(text);
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    auto cells = std::vector<std::string>();
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (line.size() && line.back() == ',') cells.push_back("");
    if (header) {
      col = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "t_x_nut_c") - cells.begin());
      header = false;
    } else {
      const double t = std::stod(cells[0]);
      if (t >= cold.start_time_s - 600 && t <= cold.end_time_s + 600) cells[col] = "";
    }
    for (std::size_t i = 0; i < cells.size(); ++i) out += (i ? "," : "") + cells[i];
    out += "\n";
  }
  WriteTextFile(path, out);
  const auto r = CheckCampaign(dir.string(), CheckOptions{});
  ASSERT_FALSE(r.file_problems.empty());
  EXPECT_NE(r.file_problems[0].find("no x_nut reading at its time"), std::string::npos) << r.file_problems[0];
}

TEST_F(CampaignCheckTest, CommandLine) {
  using testing::RunCli;
  auto r = RunCli("campaign check " + (base_ / "sim").string() + " --room-c 10,40");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Axis X:"), std::string::npos);
  EXPECT_NE(r.output.find("the model can vouch for room temperatures"), std::string::npos);
  EXPECT_NE(r.output.find("no measurement with the room above"), std::string::npos);

  const fs::path broken = Copy("cli_broken");
  const auto m = measure::ReadCampaignManifest((broken / "manifest.json").string());
  fs::remove(broken / m.measurements.front().file);
  r = RunCli("campaign check " + broken.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("File problems:"), std::string::npos);

  r = RunCli("campaign check " + base_.string());  // no manifest.json there
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("manifest.json"), std::string::npos);

  // plan → check on the empty folder: nothing measured yet, no file problem.
  const fs::path planned = base_ / "planned";
  r = RunCli("campaign plan --machine " + std::string(TRUEAXIS_SOURCE_DIR) +
             "/examples/campaign/vmc850_fanuc.toml --out " + planned.string() + " --axes X,Z --start-date 2026-03-02");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(planned / "plan.md"));
  r = RunCli("campaign check " + planned.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Axis Z: 0 test(s)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("no test at all"), std::string::npos);
  // Planned twice into the same folder: refused, the campaign kept.
  r = RunCli("campaign plan --machine " + kMachine + " --out " + planned.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  r = RunCli("campaign plan --machine " + kMachine + " --out " + (base_ / "p2").string() + " --controller okuma");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--controller"), std::string::npos);
}

}  // namespace
}  // namespace trueaxis::campaign
