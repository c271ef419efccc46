// The `trueaxis tool` commands end to end: a model file written by `tool day` is read back by
// `tool offset`; bad input exits with code 2 naming file, line and field.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

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
  EXPECT_EQ(off.output.find("warning"), std::string::npos) << off.output;

  // Against the Tv tool 2's models were trained on (the file's training.tv_range_c): just above
  // it the prediction extrapolates (a warning naming the line); a series in kelvin is refused
  // naming its line and field, and no G10 line is printed.
  const auto models = nlohmann::json::parse(std::ifstream(dir / "tool_models.json"));
  double lo = 1e9, hi = -1e9;
  for (const auto& t : models.at("tools"))
    if (t.at("tool") == 2) lo = t.at("training").at("tv_range_c")[0], hi = t.at("training").at("tv_range_c")[1];
  ASSERT_LT(lo, hi);
  EXPECT_LE(lo, 22);  // the series above lies inside: no warning
  EXPECT_GE(hi, 27);
  const auto run = [&](double last_tv_c) {
    const std::string s = Write("tv2.csv", fmt::format("time_s,tv_c\n0,{}\n60,{}\n120,{}\n", lo, hi, last_tv_c));
    return RunCli("tool offset --models " + (dir / "tool_models.json").string() + " --tools " + tools + " --tool 2 --series " + s);
  };
  const auto above = run(hi + 1);
  ASSERT_EQ(above.exit_code, 0) << above.output;
  EXPECT_NE(above.output.find("tv2.csv: 1 of 3 Tv samples (the first on line 4"), std::string::npos) << above.output;
  const auto kelvin = run(hi + 273.15);
  EXPECT_EQ(kelvin.exit_code, 2) << kelvin.output;
  EXPECT_NE(kelvin.output.find("tv2.csv:4: field 'tv_c'"), std::string::npos) << kelvin.output;
  EXPECT_EQ(kelvin.output.find("G10"), std::string::npos) << kelvin.output;
}

// A pixel that is no tool temperature after --scale/--offset (a broken value, a negative scale)
// is refused naming the image and the pixel, not averaged into Tv.
TEST_F(ToolCli, TvRefusesPixelsThatAreNoToolTemperature) {
  const std::string zones = Write("z.toml", "[[zone]]\nrow_from = 0\nrow_to = 1\ncol_from = 0\ncol_to = 1\narea_mm2 = 1\n");
  const auto tv = [&](const std::string& pixels, const std::string& options) {
    return RunCli("tool tv --image " + Write("i.csv", pixels) + " --zones " + zones + options);
  };
  const auto good = tv("20,21\n22,23\n", "");
  ASSERT_EQ(good.exit_code, 0) << good.output;
  EXPECT_NE(good.output.find("Tv 21.500 C"), std::string::npos) << good.output;
  auto r = tv("20,21\n22,1e308\n", "");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field 'pixel (1, 1)'"), std::string::npos) << r.output;
  r = tv("20,21\n22,23\n", " --scale -1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field '--scale'"), std::string::npos) << r.output;
  r = tv("20,21\n22,23\n", " --scale 100");  // raw counts taken as °C·100: 2300 °C
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field 'pixel (0, 0)'"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--scale"), std::string::npos) << r.output;
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
