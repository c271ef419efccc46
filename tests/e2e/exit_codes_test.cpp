// The README promises exit code 2 and a clear message for every bad input, command-line usage
// errors included (CLI11's own codes 104–109 leaked out before), and for output paths that
// cannot be created (raw library text and exit 1 before); --help is success.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

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

// A negative or NaN --duration-s made `run` and `web` run forever and `server`, `sim serve`,
// `terminal` stop at once with exit 0; every run-length option now refuses NaN, inf and negatives
// naming the option (checked before anything is opened, so these commands return at once).
TEST(ExitCodes, RunLengthOptionsRefuseNanInfAndNegative) {
  const std::string src = TRUEAXIS_SOURCE_DIR;
  const std::string run = "run --config " + src + "/examples/run/virtual.toml";
  const std::string missing_users = ::testing::TempDir() + "trueaxis_no_users_" + std::to_string(::getpid()) + ".db";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {run + " --duration-s -1", "--duration-s"},
      {run + " --duration-s nan", "--duration-s"},
      {run + " --duration-s inf", "--duration-s"},
      {run + " --status-interval-s nan", "--status-interval-s"},
      {"web --listen 127.0.0.1:1 --users " + missing_users + " --duration-s -1", "--duration-s"},
      {"web --listen 127.0.0.1:1 --users " + missing_users + " --duration-s nan", "--duration-s"},
      {"server --config " + src + "/examples/run/virtual.toml --duration-s nan", "--duration-s"},
      {"server --config " + src + "/examples/run/virtual.toml --status-interval-s -1", "--status-interval-s"},
      {"terminal --config " + src + "/examples/terminal/terminal.toml --duration-s nan", "--duration-s"},
      {"sim serve --machine " + src + "/examples/machines/vmc850.toml --duration-s nan", "--duration-s"},
      {"sim shop --duration-s nan", "--duration-s"},
      {"sim shop --status-interval-s inf", "--status-interval-s"},
      {"modbus probe --interval-s -1", "--interval-s"},
  };
  for (const auto& [args, option] : cases) {
    const auto r = RunCli(args);
    EXPECT_EQ(r.exit_code, 2) << "trueaxis " << args << "\n" << r.output;
    EXPECT_NE(r.output.find("error: command line: field '" + option + "': "), std::string::npos)
        << "trueaxis " << args << "\n" << r.output;
  }
  EXPECT_FALSE(std::filesystem::exists(missing_users));
}

// A unit-id layout MODBUS cannot hold (RTD modules past 247, or over the PMC window's unit id)
// exited 1 from the server's start; it is an option error now, found before anything listens.
TEST(ExitCodes, AUnitIdLayoutMODBUSCannotHoldNamesTheOption) {
  const std::string serve = "sim serve --machine " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml --duration-s 1 ";
  for (const std::string options : {"--first-rtd-unit 247", "--pmc-unit 2 --first-rtd-unit 2"}) {
    const auto r = RunCli(serve + options);
    EXPECT_EQ(r.exit_code, 2) << options << "\n" << r.output;
    EXPECT_NE(r.output.find("error: command line: field '--first-rtd-unit': "), std::string::npos) << options << "\n" << r.output;
  }
}

// `user list --users <typo>` created an empty database and exited 0 (a typo read as "no users");
// the commands that read or change users refuse a missing database and create nothing.
TEST(ExitCodes, UserCommandsOtherThanAddRefuseAMissingDatabase) {
  const std::string missing = ::testing::TempDir() + "trueaxis_no_such_users_" + std::to_string(::getpid()) + ".db";
  for (const std::string sub : {"list", "remove --name chief", "passwd --name chief --password-file /nonexistent"}) {
    const auto r = RunCli("user " + sub + " --users " + missing);
    EXPECT_EQ(r.exit_code, 2) << "user " << sub << "\n" << r.output;
    EXPECT_NE(r.output.find("error: command line: field '--users': '" + missing + "' does not exist"), std::string::npos)
        << "user " << sub << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(missing)) << "user " << sub;
  }
}

}  // namespace
