// `trueaxis vision run --relation-from`: the relation is calibrated and printed, a run above its
// speeds warns, a bad reference program exits 2 naming the option.
#include <gtest/gtest.h>

#include "support/cli_runner.hpp"

namespace {
using trueaxis::testing::RunCli;

const std::string kFiles = std::string(" --marker ") + TRUEAXIS_SOURCE_DIR + "/examples/vision/marker.toml --camera " +
                           TRUEAXIS_SOURCE_DIR + "/examples/vision/camera.yml --hours 3 --interval-s 3600";

TEST(SpindleRelationCli, ARunAboveTheCalibratedSpeedsWarnsAndABadReferenceIsRefused) {
  const auto within = RunCli("vision run" + kFiles + " --speeds 0:0,600:8000 --relation-from 0:0,600:10000,7200:0");
  ASSERT_EQ(within.exit_code, 0) << within.output;
  EXPECT_NE(within.output.find("marker-to-spindle relation"), std::string::npos) << within.output;
  EXPECT_NE(within.output.find("calibrated up to 10000 rpm"), std::string::npos) << within.output;
  EXPECT_EQ(within.output.find("warning: the spindle ran at"), std::string::npos) << within.output;

  const auto above = RunCli("vision run" + kFiles + " --speeds 0:0,600:15000 --relation-from 0:0,600:10000,7200:0");
  ASSERT_EQ(above.exit_code, 0) << above.output;
  EXPECT_NE(above.output.find("warning: the spindle ran at 15000 rpm, above the 10000 rpm"), std::string::npos) << above.output;

  const auto bad = RunCli("vision run" + kFiles + " --relation-from 0:0,600:abc");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--relation-from"), std::string::npos) << bad.output;
  const auto single = RunCli("vision run" + kFiles + " --relation-from 0:9000");
  EXPECT_EQ(single.exit_code, 2) << single.output;
  EXPECT_NE(single.output.find("must change the spindle speed"), std::string::npos) << single.output;
}

}  // namespace
