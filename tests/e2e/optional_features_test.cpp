// The CLI in this build's configuration of the optional features (cmake/TrueaxisDeps.cmake): a
// command of a feature that is built runs; one of a feature left out is still known and answers
// that this build lacks it, how to get it, and exit 1 — never "unknown command" (exit 2).
#include <gtest/gtest.h>

#include <string>

#include "support/cli_runner.hpp"

namespace {

using trueaxis::testing::RunCli;

void ExpectFeature(bool built, const std::string& args, const std::string& feature) {
  const auto r = RunCli(args);
  const std::string missing = "this build has no " + feature + " support";
  if (built) {
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find(missing), std::string::npos) << args << "\n" << r.output;
  } else {
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(missing), std::string::npos) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("bash scripts/install-deps.sh --all"), std::string::npos) << r.output;
  }
}

TEST(OptionalFeatures, VisionCommandsRunOrSayTheBuildLacksVision) {
  ExpectFeature(TRUEAXIS_HAVE_VISION, "vision measure --help", "vision");
  ExpectFeature(TRUEAXIS_HAVE_VISION, "tool day --help", "vision");
  // Left out, the answer is the same whatever follows (options it would refuse included).
  if (!TRUEAXIS_HAVE_VISION) ExpectFeature(false, "vision calibrate --no-such-option 3", "vision");
  // Listed in the overview either way.
  const auto help = RunCli("--help");
  EXPECT_NE(help.output.find("vision"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("tool"), std::string::npos) << help.output;
}

}  // namespace
