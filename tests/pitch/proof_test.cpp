// The following-error comparison of `pitch report` / `pitch proof`: bad or
// too slow --feeds are refused before any simulation.
#include <gtest/gtest.h>

#include <cmath>

#include "pitch_test_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/pitch/proof.hpp"

namespace trueaxis::sim {
namespace {

// The sweep's A4: --feeds 0.001 ran for hours (work ∝ 1/feed) and 0, -5, nan
// gave exit 1 "interpolator: feed must be positive". Every feed is now checked
// before anything runs, naming --feeds.
TEST(Interpolator, FollowingErrorVsFeedRefusesBadAndTooSlowFeedsFirst) {
  const auto machine = pitch::testing::PitchMachine();
  pitch::PitchErrorTable table;
  table.axis = "X";
  table.lead_mm = 5;
  for (int k = 0; k <= 24; ++k) {
    table.position_mm.push_back(5.0 * k);
    table.error_up_um.push_back(0);
    table.error_down_um.push_back(0);
  }
  for (double feed : {0.001, 0.0, -5.0, std::nan(""), 1e9}) {
    try {
      // The good feed first: a refusal must come before any simulation.
      pitch::FollowingErrorVsFeed(machine, 0, table, {1000, feed}, InterpolatorOptions{}, 1);
      FAIL() << "accepted " << feed;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "command line");
      EXPECT_EQ(e.field(), "--feeds") << e.what();
    }
  }
  // 120 mm at 2 mm/min is 3600 s: the slowest that fits (the message gives it).
  try {
    pitch::FollowingErrorVsFeed(machine, 0, table, {1.9}, InterpolatorOptions{}, 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 2 mm/min"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trueaxis::sim
