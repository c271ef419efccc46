// The README promises exit code 2 and a clear message for every bad input, command-line usage
// errors included (CLI11's own codes 104–109 leaked out before), and for output paths that
// cannot be created (raw library text and exit 1 before); --help is success.
#include <gtest/gtest.h>

#include <string>

#include "support/cli_runner.hpp"

namespace {

using trueaxis::testing::RunCli;

TEST(ExitCodes, UsageErrorsExitTwo) {
  for (const std::string args : {"", "analyze", "analyze --no-such-option x.csv", "fit --max-degree abc",
                                 "no-such-command", "predict --model"}) {
    const auto r = RunCli(args);
    EXPECT_EQ(r.exit_code, 2) << "trueaxis " << args << "\n" << r.output;
    EXPECT_FALSE(r.output.empty()) << "trueaxis " << args;
  }
}

TEST(ExitCodes, HelpIsSuccess) {
  EXPECT_EQ(RunCli("--help").exit_code, 0);
  EXPECT_EQ(RunCli("fit --help").exit_code, 0);
}

TEST(ExitCodes, UncreatableOutputPathsExitTwoNamingThePath) {
  const std::string machine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";
  const auto campaign = RunCli("sim campaign --machine " + machine + " --out /proc/trueaxis-no/such");
  EXPECT_EQ(campaign.exit_code, 2) << campaign.output;
  EXPECT_NE(campaign.output.find("error: /proc/trueaxis-no/such"), std::string::npos) << campaign.output;
  EXPECT_EQ(campaign.output.find("filesystem error"), std::string::npos) << campaign.output;
}

}  // namespace
