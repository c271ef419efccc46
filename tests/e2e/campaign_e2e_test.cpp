// The campaign folder end to end through the CLI: `sim campaign` writes it in the one manifest
// format, `campaign check` reads it as a real machine's campaign, the fit takes it; `campaign plan`
// of the same machine writes a folder the same reader takes.
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <unistd.h>

#include "support/cli_runner.hpp"
#include "trueaxis/core/text_file.hpp"

namespace {

namespace fs = std::filesystem;
using trueaxis::testing::RunCli;

TEST(CampaignE2E, SimCampaignIsCheckedAndFitted) {
  const fs::path dir = fs::temp_directory_path() / ("trueaxis_campaign_e2e_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::string machine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc400_small.toml";
  auto r = RunCli("sim campaign --quiet --machine " + machine + " --axes X --out " + (dir / "sim").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string manifest = trueaxis::ReadTextFile((dir / "sim" / "manifest.json").string());
  EXPECT_NE(manifest.find("\"format\": \"trueaxis-campaign\""), std::string::npos);

  r = RunCli("campaign check " + (dir / "sim").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cold           1"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("File problems"), std::string::npos) << r.output;

  r = RunCli("fit --manifest " + (dir / "sim" / "manifest.json").string() + " --out " + (dir / "model.json").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "model.json"));

  // The plan of the same (virtual) machine: the empty folder the same reader takes.
  r = RunCli("campaign plan --machine " + machine + " --axes X --controller linuxcnc --out " + (dir / "plan").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "plan" / "programs" / "linuxcnc" / "X_laser5_linuxcnc.ngc"));
  r = RunCli("campaign check " + (dir / "plan").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("Axis X: 0 test(s)"), std::string::npos) << r.output;
  // Nothing to fit yet: refused, naming the manifest.
  r = RunCli("fit --manifest " + (dir / "plan" / "manifest.json").string() + " --out " + (dir / "m2.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lists no measurement files"), std::string::npos) << r.output;
  fs::remove_all(dir);
}

}  // namespace
