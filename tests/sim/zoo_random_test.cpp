// bench/zoo_random.py (issue 10): the random machines are valid machine files, span the ranges the
// issue names, and the same seed gives the same machines.
#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {
namespace {

namespace fs = std::filesystem;

struct Generated {
  int exit_code = -1;
  std::vector<std::string> paths;  // one per line of stdout
  std::string output;
};

Generated RunGenerator(const std::string& args, const fs::path& out) {
  const std::string cmd = "/usr/bin/python3 " + std::string(TRUEAXIS_SOURCE_DIR) + "/bench/zoo_random.py " + args +
                          " --out " + out.string() + " 2>&1";
  Generated g;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return g;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) g.output.append(buf.data(), n);
  const int status = pclose(p);
  g.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::istringstream lines(g.output);
  for (std::string line; std::getline(lines, line);)
    if (line.size() > 5 && line.substr(line.size() - 5) == ".toml") g.paths.push_back(line);
  return g;
}

std::string ReadAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

class ZooRandom : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("trueaxis_zoo_random_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(ZooRandom, MachinesAreValidAndSpanTheIssuesRanges) {
  const auto g = RunGenerator("--seed 7 --count 30", dir_ / "a");
  ASSERT_EQ(g.exit_code, 0) << g.output;
  ASSERT_EQ(g.paths.size(), 30u) << g.output;
  std::set<FixedEnd> ends;
  std::set<std::size_t> axis_counts;
  double travel_lo = 1e9, travel_hi = 0;
  int faults = 0, lathes = 0;
  for (const auto& path : g.paths) {
    SCOPED_TRACE(path);
    const MachineDescription m = ReadMachineFile(path);  // throws InputError on anything invalid
    ASSERT_FALSE(m.axes.empty());
    axis_counts.insert(m.axes.size());
    lathes += m.axes.size() == 2 && m.axes[0].name == "X" && m.axes[1].name == "Z";
    EXPECT_GE(m.ambient.mean_c, 15.0);
    EXPECT_LE(m.ambient.mean_c, 30.0);
    EXPECT_GE(m.ambient.daily_amplitude_c, 0.5);
    EXPECT_LE(m.ambient.daily_amplitude_c, 3.0);
    for (const auto& a : m.axes) {
      EXPECT_GE(a.travel_mm, 200.0) << a.name;
      EXPECT_LE(a.travel_mm, 2000.0) << a.name;
      EXPECT_GE(a.lead_mm, 5.0) << a.name;
      EXPECT_LE(a.lead_mm, 25.0) << a.name;
      // Half to three times vmc850's nut heat (24 W), each axis jittered by ±20 %.
      EXPECT_GE(a.thermal.nut_heat_w, 0.5 * 24 * 0.8 - 0.05) << a.name;
      EXPECT_LE(a.thermal.nut_heat_w, 3.0 * 24 * 1.2 + 0.05) << a.name;
      ends.insert(a.fixed_end);
      travel_lo = std::min(travel_lo, a.travel_mm);
      travel_hi = std::max(travel_hi, a.travel_mm);
    }
    // Every machine names its sensors (nut, bearing, motor per axis, room, bed).
    EXPECT_EQ(m.sensors.size(), 3 * m.axes.size() + 2);
    faults += static_cast<int>(m.day_faults.size());
  }
  EXPECT_EQ(ends.size(), 2u) << "the thrust bearing at both ends across the set";
  EXPECT_GE(axis_counts.size(), 2u) << "machines with different numbers of axes";
  EXPECT_GT(lathes, 0);
  EXPECT_GT(faults, 0) << "some machine loses a sensor during the day";
  EXPECT_LT(travel_lo, 400.0);
  EXPECT_GT(travel_hi, 1500.0);
}

TEST_F(ZooRandom, TheSameSeedGivesTheSameMachinesAndAnotherSeedOthers) {
  const auto a = RunGenerator("--seed 11 --count 4", dir_ / "a");
  const auto b = RunGenerator("--seed 11 --count 4", dir_ / "b");
  const auto c = RunGenerator("--seed 12 --count 4", dir_ / "c");
  ASSERT_EQ(a.exit_code, 0) << a.output;
  ASSERT_EQ(a.paths.size(), 4u);
  ASSERT_EQ(b.paths.size(), 4u);
  ASSERT_EQ(c.paths.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(fs::path(a.paths[i]).filename(), fs::path(b.paths[i]).filename());
    EXPECT_EQ(ReadAll(a.paths[i]), ReadAll(b.paths[i])) << a.paths[i];
    EXPECT_NE(ReadAll(a.paths[i]), ReadAll(c.paths[i])) << c.paths[i];
  }
}

TEST_F(ZooRandom, ACountBelowOneIsRefused) {
  const auto g = RunGenerator("--count 0", dir_ / "a");
  EXPECT_NE(g.exit_code, 0);
  EXPECT_NE(g.output.find("--count must be at least 1"), std::string::npos) << g.output;
  EXPECT_FALSE(fs::exists(dir_ / "a"));
}

}  // namespace
}  // namespace trueaxis::sim
