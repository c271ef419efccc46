// trueaxis-demo, the program scripts/demo.sh builds and runs first: the `demo` command alone, over
// the modules the demo runs, answering as `trueaxis demo` does.
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "support/cli_runner.hpp"

namespace {

using trueaxis::testing::RunShell;

std::string DemoProgram() { return TRUEAXIS_DEMO_CLI_PATH; }

TEST(DemoProgram, OffersTheDemoCommandAndNoOther) {
  const auto r = RunShell(DemoProgram() + " --help 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::regex_search(r.output, std::regex(R"(\n +demo {2,}End-to-end demo)"))) << r.output;
  EXPECT_FALSE(std::regex_search(r.output, std::regex(R"(\n +analyze )"))) << r.output;
  EXPECT_EQ(RunShell(DemoProgram() + " analyze x.csv 2>&1").exit_code, 2);
}

TEST(DemoProgram, HasTheVersionOfTrueaxis) {
  const auto demo = RunShell(DemoProgram() + " --version");
  EXPECT_EQ(demo.exit_code, 0);
  EXPECT_NE(demo.output.find("trueaxis "), std::string::npos) << demo.output;
  EXPECT_EQ(demo.output, RunShell(std::string(TRUEAXIS_CLI_PATH) + " --version").output);
}

TEST(DemoProgram, AMissingMachineFileIsAnInputErrorNamingIt) {
  const auto r = RunShell(DemoProgram() + " demo --fast --quiet --machine /nonexistent/machine.toml --out " +
                          ::testing::TempDir() + "trueaxis_demo_program 2>&1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("/nonexistent/machine.toml"), std::string::npos) << r.output;
}

}  // namespace
