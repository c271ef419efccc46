// Machine file reader: the example loads; bad files name file, line and key.
#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim {
namespace {

TEST(MachineFile, ExampleVmc850Loads) {
  const auto m = ReadMachineFile(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml");
  EXPECT_EQ(m.name, "VMC-850");
  ASSERT_EQ(m.axes.size(), 3u);
  EXPECT_EQ(m.axes[0].name, "X");
  EXPECT_DOUBLE_EQ(m.axes[0].travel_mm, 850);
  EXPECT_EQ(m.axes[2].fixed_end, FixedEnd::kMax);
  EXPECT_DOUBLE_EQ(m.axes[2].reference_mm, 500);  // defaults to the fixed-end side
  EXPECT_EQ(m.sensors.size(), 11u);
  for (const auto& s : m.sensors) {
    EXPECT_FALSE(std::isnan(s.offset_c)) << s.name;
    EXPECT_FALSE(std::isnan(s.noise_c)) << s.name;
  }
  EXPECT_EQ(m.AxisIndex("y"), 1);
}

TEST(MachineFile, DefaultSensorsWhenNoneListed) {
  const auto m = testing::TestMachine();
  std::vector<std::string> names;
  for (const auto& s : m.sensors) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"x_nut", "x_bearing", "x_motor", "y_nut", "y_bearing", "y_motor", "ambient", "bed"}));
}

using testing::ExpectBad;

const std::string kAxis = "[[axis]]\nname = \"X\"\ntravel_mm = 500\nlead_mm = 10\n";  // lines 1–4

TEST(MachineFile, BadFilesNameLineAndKey) {
  ExpectBad({"syntax", "[machine\nname = 1\n", 1, ""});
  ExpectBad({"unknown key", kAxis + "travl_mm = 3\n", 5, "axis[0].travl_mm"});
  ExpectBad({"wrong type", kAxis + "backlash_um = \"five\"\n", 5, "axis[0].backlash_um"});
  ExpectBad({"out of range", "[[axis]]\nname = \"X\"\ntravel_mm = 500\nlead_mm = 0\n", 4, "axis[0].lead_mm"});
  ExpectBad({"negative backlash", kAxis + "backlash_um = -2\n", 5, "axis[0].backlash_um"});
  ExpectBad({"missing travel", "[[axis]]\nname = \"X\"\nlead_mm = 10\n", 1, "axis[0].travel_mm"});
  ExpectBad({"bad fixed end", kAxis + "fixed_end = \"left\"\n", 5, "axis[0].fixed_end"});
  ExpectBad({"reference outside travel", kAxis + "reference_mm = 600\n", 5, "axis[0].reference_mm"});
  ExpectBad({"duplicate axis", kAxis + kAxis, 6, "axis[1].name"});
  ExpectBad({"pitch typo", kAxis + "[axis.pitch]\nprogresive_um = 3\n", 6, "axis[0].pitch.progresive_um"});
  ExpectBad({"thermal range", kAxis + "[axis.thermal]\nscrew_segments = 1\n", 6, "axis[0].thermal.screw_segments"});
  ExpectBad({"sensor name", kAxis + "[[sensor]]\nname = \"X Nut\"\n", 6, "sensor[0].name"});
  ExpectBad({"sensor location", kAxis + "[[sensor]]\nname = \"spindle\"\n", 6, "sensor[0].location"});
  ExpectBad({"sensor kind", kAxis + "[[sensor]]\nname = \"x_nut\"\nkind = \"thermocouple\"\n", 7, "sensor[0].kind"});
  ExpectBad({"ambient typo", kAxis + "[ambient]\nmean = 20\n", 6, "ambient.mean"});
  ExpectBad({"bad start", "[machine]\nstart = \"yesterday\"\n" + kAxis, 2, "machine.start"});
  ExpectBad({"unknown table", kAxis + "[spindle]\nrpm = 1\n", 5, "spindle"});
  ExpectBad({"coolant state", kAxis + "[coolant.flood]\nnut_w_per_k = -1\n", 6, "coolant.flood.nut_w_per_k"});
}

TEST(MachineFile, NoAxesIsAnError) {
  EXPECT_THROW(ParseMachineToml("[machine]\nname = \"x\"\n", "bad.toml"), InputError);
}

TEST(MachineFile, MissingFileIsAnInputError) {
  EXPECT_THROW(ReadMachineFile("/nonexistent/machine.toml"), InputError);
}

}  // namespace
}  // namespace trueaxis::sim

namespace trueaxis::sim {
namespace {

// A machine file cut short at a table boundary is valid TOML; the declared axis list catches it.
TEST(MachineFileTruncation, AFileCutAfterItsFirstAxisIsRefused) {
  const std::string path = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const auto second_axis = text.find("\n[[axis]]", text.find("\n[[axis]]") + 1);
  ASSERT_NE(second_axis, std::string::npos);
  try {
    ParseMachineToml(text.substr(0, second_axis), "cut.toml");
    ADD_FAILURE() << "a machine file cut after its first axis was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cut.toml:"), std::string::npos) << what;
    EXPECT_NE(what.find("machine.axes"), std::string::npos) << what;
    EXPECT_NE(what.find("cut short"), std::string::npos) << what;
  }
  EXPECT_EQ(ParseMachineToml(text, "whole.toml").axes.size(), 3u);
}

}  // namespace
}  // namespace trueaxis::sim
