// The `trueaxis tool` commands end to end: a model file written by `tool day` is read back by
// `tool offset`; bad input exits with code 2 naming file, line and field.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "support/cli_runner.hpp"

namespace {
namespace fs = std::filesystem;
using trueaxis::testing::RunCli;

class ToolCli : public ::testing::Test {
 protected:
  fs::path dir = fs::temp_directory_path() / ("tooltherm_cli_" + std::to_string(::getpid()));
  std::string tools = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/tool/tools.toml";
  void SetUp() override { fs::create_directories(dir); }
  void TearDown() override { fs::remove_all(dir); }
  std::string Write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  }
};

TEST_F(ToolCli, DayWritesModelsThatOffsetAppliesAsAToolLengthOffset) {
  const auto day = RunCli("tool day --tools " + tools + " --hours 1 --sample-s 10 --sensor pyrometer --out " + dir.string());
  ASSERT_EQ(day.exit_code, 0) << day.output;
  EXPECT_NE(day.output.find("| T2 "), std::string::npos) << day.output;
  const std::string series = Write("tv.csv", "time_s,tv_c\n0,22\n60,24\n120,26\n180,27\n");
  const auto off = RunCli("tool offset --models " + (dir / "tool_models.json").string() + " --tools " + tools +
                          " --tool 2 --series " + series + " --model one");
  ASSERT_EQ(off.exit_code, 0) << off.output;
  EXPECT_NE(off.output.find("G10 L1 P2 Z160.0"), std::string::npos) << off.output;
  EXPECT_NE(off.output.find("T2 P2 Z+160.0"), std::string::npos) << off.output;
}

TEST_F(ToolCli, BadInputExitsWithTwoAndNamesThePlace) {
  const std::string zones = Write("z.toml", "[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 1\narea_mm2 = 0\n");
  const std::string image = Write("i.csv", "20,21\n22,23\n");
  auto r = RunCli("tool tv --image " + image + " --zones " + zones);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("z.toml:6: field 'zone[0].area_mm2'"), std::string::npos) << r.output;
  const std::string bad_tools = Write("t.toml", "[[tool]]\nnumber = 1\nlength_mm = 40\ndiameter_mm = 10\nmaterial = \"wood\"\n");
  r = RunCli("tool day --tools " + bad_tools + " --hours 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("t.toml:5: field 'tool[0].material'"), std::string::npos) << r.output;
  r = RunCli("tool day --random-tools 2 --hours 1 --sensor sonar");
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
