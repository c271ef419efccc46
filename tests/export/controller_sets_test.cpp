// The controller-specific decisions that moved from the CLI into export/: the HEIDENHAIN set of
// thermal states and the SINUMERIK value at the reference point.
#include <cmath>

#include <gtest/gtest.h>

#include "example_model.hpp"
#include "trueaxis/export/heidenhain_states.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/sinumerik_table.hpp"

namespace trueaxis::exporter {
namespace {
using testing::ExampleAxis;

ResampleOptions Frozen(CoolantState coolant) {
  ResampleOptions o;
  o.spacing_mm = 20;
  o.thermal.temperatures_c = {{"nut", 30}, {"bearing", 26}};
  o.thermal.coolant = coolant;
  return o;
}

TEST(HeidenhainStates, ColdPlusOneStatePerFittedCoolantWithTheRequestedOneActive) {
  const auto states = HeidenhainModelStates(ExampleAxis(), Frozen(CoolantState::kFlood), "example");
  ASSERT_EQ(states.size(), 3u);  // COLD, OFF, FLOOD (the model has gains for off and flood)
  EXPECT_EQ(states[0].name, "COLD");
  EXPECT_FALSE(states[0].active);
  EXPECT_EQ(states[1].name, "OFF");
  EXPECT_FALSE(states[1].active);
  EXPECT_EQ(states[2].name, "FLOOD");
  EXPECT_TRUE(states[2].active);
  // The warm tables differ from the cold one (the thermal part is frozen in), flood less than off.
  const double x = 400;
  const double cold = AppliedCorrectionUm(states[0].table, x, Direction::kForward);
  const double off = AppliedCorrectionUm(states[1].table, x, Direction::kForward);
  const double flood = AppliedCorrectionUm(states[2].table, x, Direction::kForward);
  EXPECT_GT(std::fabs(off - cold), std::fabs(flood - cold));
  EXPECT_GT(std::fabs(flood - cold), 0.1);
}

TEST(HeidenhainStates, WithoutAThermalStateOnlyTheColdTableIsActive) {
  ResampleOptions o;
  o.spacing_mm = 20;
  const auto states = HeidenhainModelStates(ExampleAxis(), o, "example");
  ASSERT_EQ(states.size(), 1u);
  EXPECT_TRUE(states[0].active);
}

TEST(HeidenhainStates, ACoolantWithoutGainsLeavesNoStateActive) {
  const auto states = HeidenhainModelStates(ExampleAxis(), Frozen(CoolantState::kMist), "example");
  for (const auto& s : states) EXPECT_FALSE(s.active) << s.name;
}

TEST(HeidenhainStates, TheSetNamesItsComFilesAfterTheCmaAndListsThemActiveOnce) {
  const auto states = HeidenhainModelStates(ExampleAxis(), Frozen(CoolantState::kOff), "example");
  const auto files = WriteHeidenhainSet(states, "X", "x_axis.CMA", ValueSign::kCorrection, "test");
  ASSERT_EQ(files.size(), 4u);
  EXPECT_EQ(files[0].file_name, "X_AXIS_COLD.COM");
  EXPECT_EQ(files[3].file_name, "x_axis.CMA");
  const auto lines = ReadHeidenhainCma(files[3].text, "X", "x_axis.CMA");
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_TRUE(lines[1].active);  // OFF
  const auto cold = ReadHeidenhainCom(files[0].text, ValueSign::kCorrection, files[0].file_name);
  EXPECT_EQ(cold.position_mm.size(), states[0].table.position_mm.size());
}

TEST(SinumerikReference, TheValueAtTheReferenceAndNaNOutsideTheTable) {
  ResampleOptions o;
  o.spacing_mm = 20;
  o.reference_position_mm = 100;
  CompensationTable t = ResampleModel(ExampleAxis(), o, "example").table;
  const double at_ref = SinumerikValueAtReferenceUm(t);
  ASSERT_TRUE(std::isfinite(at_ref));
  EXPECT_NEAR(at_ref, -(AppliedCorrectionUm(t, 100, Direction::kForward) - 0.5 * t.backlash_um), 1e-9);
  t.reference_position_mm = t.position_mm.back() + 50;
  EXPECT_TRUE(std::isnan(SinumerikValueAtReferenceUm(t)));
}

}  // namespace
}  // namespace trueaxis::exporter
