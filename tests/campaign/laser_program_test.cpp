// The NC programs of the plan: for every controller the laser test reads back as the targets in
// order, up and down, each run, the dwell at every target and the overrun beyond both ends; each
// program has its dialect's frame; LinuxCNC's is run through the rs274 interpreter when installed.
#include "trueaxis/campaign/laser_program.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "trueaxis/core/text_file.hpp"

namespace trueaxis::campaign {
namespace {

CampaignMachine Machine() {
  CampaignMachine m;
  m.name = "test machine";
  m.axes = {{"X", -850, 0, 12, false, 0}, {"Y", 0, 500, 10, true, 0}};
  return m;
}

// A program read back: the axis position after each motion line (machine coordinates, µm) and
// whether a dwell follows it.
std::vector<ProgramStep> ReadBack(Controller c, const std::string& text, const std::string& axis) {
  std::vector<ProgramStep> steps;
  std::istringstream in(text);
  std::string line;
  long long at_um = 0;
  bool incremental = false;
  const std::regex word(axis + (c == Controller::kSinumerik ? "=" : "") + "([-+]?[0-9]+\\.[0-9]+)");
  while (std::getline(in, line)) {
    const auto comment = line.find_first_of(c == Controller::kSinumerik || c == Controller::kHeidenhain ? ";" : "(");
    const std::string code = line.substr(0, comment);
    const bool dwell = (c == Controller::kLinuxCnc && code.rfind("G4 P", 0) == 0) ||
                       (c == Controller::kFanuc && code.rfind("G04 X", 0) == 0) ||
                       (c == Controller::kSinumerik && code.rfind("G4 F", 0) == 0) ||
                       (c == Controller::kHeidenhain && code.find("CYCL DEF 9.1 DWELL") != std::string::npos);
    if (dwell) {
      EXPECT_FALSE(steps.empty());
      if (!steps.empty()) steps.back().dwell = true;
      continue;
    }
    if (c == Controller::kFanuc && code.find("G91") != std::string::npos) incremental = true;
    std::smatch m;
    if (!std::regex_search(code, m, word)) continue;
    const long long um = std::llround(std::stod(m[1]) * 1000);
    at_um = incremental ? at_um + um : um;
    steps.push_back({static_cast<double>(at_um) / 1000, false});
  }
  return steps;
}

TEST(LaserProgram, StepsAreTheBidirectionalCycle) {
  AxisTargets t;
  t.targets_mm = {-844, -600.5, -400, -6};
  t.overrun_mm = 5;
  const auto s = LaserTestSteps(t, 2);
  ASSERT_EQ(s.size(), 2u * (2 + 2 * 4));
  for (int run = 0; run < 2; ++run) {
    const std::size_t b = static_cast<std::size_t>(run) * 10;
    EXPECT_DOUBLE_EQ(s[b].position_mm, -849);  // below the first target by the overrun
    EXPECT_FALSE(s[b].dwell);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_DOUBLE_EQ(s[b + 1 + i].position_mm, t.targets_mm[i]);  // up
      EXPECT_TRUE(s[b + 1 + i].dwell);
    }
    EXPECT_DOUBLE_EQ(s[b + 5].position_mm, -1);  // above the last by the overrun
    EXPECT_FALSE(s[b + 5].dwell);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(s[b + 6 + i].position_mm, t.targets_mm[3 - i]);  // down
  }
}

TEST(LaserProgram, EveryControllerRunsTheTargetsBothWaysWithTheDwell) {
  const auto m = Machine();
  TargetOptions o;
  const auto t = PlanAxisTargets(m.axes[0], o);
  const auto expected = LaserTestSteps(t, 3);
  for (Controller c : AllControllers()) {
    SCOPED_TRACE(std::string(ControllerName(c)));
    const auto p = LaserTestProgram(c, m, m.axes[0], t, 3, 7001);
    const auto got = ReadBack(c, p.text, "X");
    ASSERT_EQ(got.size(), expected.size()) << p.text.substr(0, 600);
    for (std::size_t i = 0; i < got.size(); ++i) {
      EXPECT_NEAR(got[i].position_mm, expected[i].position_mm, 1e-9) << "step " << i;
      EXPECT_EQ(got[i].dwell, expected[i].dwell) << "step " << i;
    }
    // The dwell's value.
    EXPECT_NE(p.text.find(c == Controller::kLinuxCnc    ? "G4 P3\n"
                          : c == Controller::kFanuc     ? "G04 X3.0\n"
                          : c == Controller::kSinumerik ? "G4 F3\n"
                                                        : "CYCL DEF 9.1 DWELL 3\n"),
              std::string::npos);
  }
}

TEST(LaserProgram, DialectFrames) {
  const auto m = Machine();
  const auto t = PlanAxisTargets(m.axes[1], TargetOptions{});
  const auto lc = LaserTestProgram(Controller::kLinuxCnc, m, m.axes[1], t, 5, 7011).text;
  EXPECT_EQ(lc.rfind("%\n", 0), 0u);
  EXPECT_NE(lc.find("\nM2\n%\n"), std::string::npos);
  // Every motion in machine coordinates at the laser feed.
  for (std::size_t at = lc.find("Y"); at != std::string::npos; at = lc.find("\nG", at + 1)) {
    const std::string line = lc.substr(at + 1, lc.find('\n', at + 1) - at - 1);
    if (line.rfind("G1", 0) == 0 || line.rfind("G53", 0) == 0) {
      EXPECT_EQ(line.rfind("G53 G1 Y", 0), 0u) << line;
      EXPECT_NE(line.find(" F2000"), std::string::npos) << line;
    }
  }
  const auto fanuc = LaserTestProgram(Controller::kFanuc, m, m.axes[1], t, 5, 7011);
  EXPECT_EQ(fanuc.text.rfind("%\nO7011 ", 0), 0u);
  EXPECT_NE(fanuc.text.find("\nG90\nM30\n%\n"), std::string::npos);
  EXPECT_EQ(fanuc.file_name, "O7011_Y_laser5_fanuc.nc");
  for (char ch : fanuc.text) EXPECT_FALSE(ch >= 'a' && ch <= 'z') << "FANUC text in upper case";
  const auto sin = LaserTestProgram(Controller::kSinumerik, m, m.axes[1], t, 5, 7011);
  EXPECT_EQ(sin.file_name, "TA_Y_LASER5.MPF");
  EXPECT_NE(sin.text.find("G1 SUPA Y="), std::string::npos);
  EXPECT_EQ(sin.text.substr(sin.text.size() - 4), "M30\n");
  const auto hh = LaserTestProgram(Controller::kHeidenhain, m, m.axes[1], t, 5, 7011);
  EXPECT_EQ(hh.file_name, "TAYLASER5.H");
  // Blocks numbered from 0 without a gap; BEGIN and END name the file's program.
  std::istringstream in(hh.text);
  std::string line;
  int n = 0;
  std::string last;
  while (std::getline(in, line)) {
    EXPECT_EQ(line.rfind(std::to_string(n) + " ", 0), 0u) << line;
    ++n;
    last = line;
  }
  EXPECT_EQ(hh.text.rfind("0 BEGIN PGM TAYLASER5 MM\n", 0), 0u);
  EXPECT_NE(last.find("END PGM TAYLASER5 MM"), std::string::npos);
  EXPECT_NE(hh.text.find(" R0 F2000 M91\n"), std::string::npos);
}

TEST(LaserProgram, WarmUpAlternatesTheFeedsOverEveryAxis) {
  const auto m = Machine();
  for (Controller c : AllControllers()) {
    SCOPED_TRACE(std::string(ControllerName(c)));
    const auto p = WarmUpProgram(c, m, {"X", "Y"}, 2000, 4000, 7900);
    // Inside the limits with the virtual warm-up's margin (10 mm).
    const auto xs = ReadBack(c, p.text, "X");
    ASSERT_GE(xs.size(), 3u);
    for (const auto& s : xs) {
      EXPECT_GE(s.position_mm, -840 - 1e-9);
      EXPECT_LE(s.position_mm, -10 + 1e-9);
    }
    EXPECT_NE(p.text.find(c == Controller::kLinuxCnc    ? "o100 repeat"
                          : c == Controller::kFanuc     ? "M99"
                          : c == Controller::kSinumerik ? "ENDLOOP"
                                                        : "CALL LBL 1"),
              std::string::npos);
  }
  // The longest axis (X, 830 mm) at the stroke's feed: path feed = 2000 · √(830² + 480²)/830.
  const auto lc = WarmUpProgram(Controller::kLinuxCnc, m, {"X", "Y"}, 2000, 4000, 7900).text;
  EXPECT_NE(lc.find(fmt::format(" F{}", std::llround(2000 * std::hypot(830.0, 480.0) / 830))), std::string::npos) << lc;
  EXPECT_NE(lc.find(fmt::format(" F{}", std::llround(4000 * std::hypot(830.0, 480.0) / 830))), std::string::npos) << lc;
}

// The LinuxCNC interpreter reads the program to its end without an error, and its canonical moves
// reach every target.
TEST(LaserProgram, LinuxCncInterpreterReadsIt) {
  if (std::system("command -v rs274 > /dev/null 2>&1") != 0) GTEST_SKIP() << "rs274 (LinuxCNC) not installed";
  const auto m = Machine();
  const auto t = PlanAxisTargets(m.axes[1], TargetOptions{});
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_campaign_rs274_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const auto& p : {LaserTestProgram(Controller::kLinuxCnc, m, m.axes[1], t, 2, 7011),
                        WarmUpProgram(Controller::kLinuxCnc, m, {"X", "Y"}, 2000, 4000, 7900)}) {
    const auto ngc = (dir / p.file_name).string(), out = ngc + ".canon";
    WriteTextFile(ngc, p.text);
    const std::string cmd = "rs274 " + ngc + " " + out + " < /dev/null > " + out + ".log 2>&1";
    const int rc = std::system(cmd.c_str());
    const std::string canon = ReadTextFile(out);
    const std::string log = ReadTextFile(out + ".log");
    EXPECT_EQ(rc, 0) << log;
    // Read to the end: the program's last canonical call is the end of program (M2).
    EXPECT_NE(canon.find("PROGRAM_END"), std::string::npos) << log;
    if (p.file_name.find("laser") != std::string::npos) {
      EXPECT_NE(canon.find("STRAIGHT_FEED"), std::string::npos);
      EXPECT_NE(canon.find("DWELL(3"), std::string::npos) << canon.substr(0, 2000);
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::campaign
