// Every run configuration in examples/run/ is read by the real config reader (the one `trueaxis
// run` and trueaxis-hal use), so an example a user copies can never rot: an unknown or misspelt
// key, a value out of range or a missing required table fails here.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/station/site_config.hpp"

namespace trueaxis::station {
namespace {
namespace fs = std::filesystem;

std::vector<fs::path> ExampleConfigs() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(TRUEAXIS_SOURCE_DIR) / "examples/run"))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ExampleRunConfigs, EveryOneIsReadByTheRealReader) {
  const auto configs = ExampleConfigs();
  std::vector<std::string> names;
  for (const auto& p : configs) names.push_back(p.filename().string());
  // The ones the docs name: the virtual machine, a MODBUS terminal, LinuxCNC.
  for (const char* wanted : {"virtual.toml", "modbus.toml", "linuxcnc.toml"})
    EXPECT_NE(std::find(names.begin(), names.end(), wanted), names.end()) << wanted << " is missing in examples/run/";
  for (const auto& p : configs) {
    SCOPED_TRACE(p.string());
    try {
      const SiteConfig c = ReadSiteConfig(p.string());
      EXPECT_FALSE(c.installation.model_file.empty());
      EXPECT_GT(c.installation.period_s, 0);
      if (c.machine == MachineKind::kModbus) EXPECT_FALSE(c.modbus.axis_names.empty());
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
}

// The LinuxCNC example says what it says in its comments: three axes with 0.1 µm counts, the
// terminal's channels, the direction threshold.
TEST(ExampleRunConfigs, LinuxCncExampleMeansWhatItsCommentsSay) {
  const SiteConfig c = ReadSiteConfig(std::string(TRUEAXIS_SOURCE_DIR) + "/examples/run/linuxcnc.toml");
  EXPECT_EQ(c.machine, MachineKind::kModbus);
  EXPECT_EQ(c.modbus.axis_names, (std::vector<std::string>{"X", "Y", "Z"}));
  ASSERT_EQ(c.installation.axes.size(), 3u);
  for (const auto& a : c.installation.axes) EXPECT_DOUBLE_EQ(a.pulse_equivalent_um, 0.1) << a.axis;
  EXPECT_DOUBLE_EQ(c.installation.period_s, 0.005);
  EXPECT_DOUBLE_EQ(c.installation.compensator.direction_min_move_um, 2.0);
  EXPECT_NE(std::find(c.modbus.channel_names.begin(), c.modbus.channel_names.end(), "ambient"), c.modbus.channel_names.end());
}

}  // namespace
}  // namespace trueaxis::station
