#include "trueaxis/export/compensation_table.hpp"

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::exporter {
namespace {

TEST(CompensationTable, InterpolatesAndHoldsEnds) {
  CompensationTable t;
  t.position_mm = {0, 10, 20};
  t.forward_um = {0, 10, 0};
  t.reverse_um = {1, 1, 1};
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 5, Direction::kForward), 5);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 15, Direction::kForward), 5);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, -5, Direction::kForward), 0);
  EXPECT_DOUBLE_EQ(AppliedCorrectionUm(t, 25, Direction::kReverse), 1);
}
}  // namespace
}  // namespace trueaxis::exporter
