#include "trueaxis/core/duration_text.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace trueaxis {
namespace {

TEST(FormatDuration, ReadsAsAHowLongNotAWhen) {
  EXPECT_EQ(FormatDuration(12.46), "12.5 s");
  EXPECT_EQ(FormatDuration(200), "3 min 20 s");
  EXPECT_EQ(FormatDuration(14 * 3600 + 5 * 60 + 10), "14:05 h");
  EXPECT_EQ(FormatDuration(26.5 * 3600), "1 d 02:30");
  EXPECT_EQ(FormatDuration(250 * 86400.0), "250 d 00:00");
  EXPECT_EQ(FormatDuration(3599.6), "1:00 h");  // rounded up into the next unit, not "60 min"
  EXPECT_EQ(FormatDuration(-1), "—");
  EXPECT_EQ(FormatDuration(std::nan("")), "—");
}

}  // namespace
}  // namespace trueaxis
