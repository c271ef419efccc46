#include "trueaxis/export/resample.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "example_model.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::exporter {
namespace {

using testing::ExampleAxis;

std::string FieldOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.field();
  }
  return "<no error>";
}

TEST(Resample, DerivedGridIsTheSmallest125StepThatFitsAndHitsTheReference) {
  ResampleOptions o;
  o.max_points = 41;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  // 400 mm / 41 points → 10 mm is the smallest 1-2-5 step with ≤ 41 points.
  ASSERT_EQ(r.table.size(), 41u);
  EXPECT_DOUBLE_EQ(r.table.position_mm.front(), 0);
  EXPECT_DOUBLE_EQ(r.table.position_mm.back(), 400);
  EXPECT_DOUBLE_EQ(r.table.UniformSpacingMm(), 10);
  o.max_points = 40;  // no longer fits: 20 mm
  EXPECT_DOUBLE_EQ(ResampleModel(ExampleAxis(), o, "m.json").table.UniformSpacingMm(), 20);
}

TEST(Resample, ValuesAreMinusTheModelErrorAtEveryPoint) {
  const auto axis = ExampleAxis();
  ResampleOptions o;
  o.spacing_mm = 25;
  const auto r = ResampleModel(axis, o, "m.json");
  model::ThermalState cold;
  cold.use_thermal = false;
  for (std::size_t i = 0; i < r.table.size(); ++i) {
    const double x = r.table.position_mm[i];
    EXPECT_DOUBLE_EQ(r.table.forward_um[i], -model::Predict(axis, x, Direction::kForward, cold).total_um);
    EXPECT_DOUBLE_EQ(r.table.reverse_um[i], -model::Predict(axis, x, Direction::kReverse, cold).total_um);
  }
}

TEST(Resample, ThermalPartIsFrozenAtTheGivenTemperaturesAndCoolant) {
  const auto axis = ExampleAxis();
  ResampleOptions o;
  o.spacing_mm = 50;
  o.thermal.temperatures_c = {{"nut", 30}, {"bearing", 26}};
  o.thermal.coolant = CoolantState::kFlood;
  const auto r = ResampleModel(axis, o, "m.json");
  const std::vector<double> temps = {30, 26};
  model::ThermalState s;
  s.key_temp_c = temps;
  s.coolant = CoolantState::kFlood;
  for (std::size_t i = 0; i < r.table.size(); ++i) {
    const double x = r.table.position_mm[i];
    EXPECT_NEAR(r.table.forward_um[i], -model::Predict(axis, x, Direction::kForward, s).total_um, 1e-12);
  }
  // flood gains: tanβ = −0.005·10 − 0.002·6 = −0.062 µm/mm
  EXPECT_NEAR(r.tan_beta_forward_um_per_mm, -0.062, 1e-12);
  // At 400 mm the thermal error is tanβ·(0 − 400) = +24.8 µm, so the correction drops by 24.8 µm.
  ResampleOptions cold = o;
  cold.thermal.temperatures_c.clear();
  const auto c = ResampleModel(axis, cold, "m.json");
  EXPECT_NEAR(c.table.forward_um.back() - r.table.forward_um.back(), 24.8, 1e-9);
}

TEST(Resample, ThermalLineKeptOutOfTheTableWhenAsked) {
  ResampleOptions o;
  o.spacing_mm = 50;
  o.thermal.temperatures_c = {{"nut", 25}, {"bearing", 22}};
  o.thermal_in_table = false;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  EXPECT_NEAR(r.table.thermal_tan_beta_um_per_mm, -0.010 * 5 - 0.004 * 2, 1e-12);
  // Applying the table (geometric values + line) equals the frozen model.
  o.thermal_in_table = true;
  const auto full = ResampleModel(ExampleAxis(), o, "m.json");
  for (double x : {0.0, 75.0, 400.0})
    EXPECT_NEAR(AppliedCorrectionUm(r.table, x, Direction::kForward),
                AppliedCorrectionUm(full.table, x, Direction::kForward), 1e-9);
}

TEST(Resample, BadThermalOptionsNameTheOption) {
  ResampleOptions o;
  o.thermal.temperatures_c = {{"spindle", 30}};
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--temp");
  o.thermal.temperatures_c = {{"nut", 30}};  // bearing missing
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--temp");
  o.thermal.temperatures_c = {{"nut", 300}, {"bearing", 20}};
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--temp");
}

TEST(Resample, LimitsAreCheckedNeverClipped) {
  ResampleOptions o;
  o.spacing_mm = 1;  // 401 points
  o.max_points = 256;
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--spacing");
  o = {};
  o.count = 300;
  o.max_points = 256;
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--count");
  o = {};
  o.range_min_mm = -50;  // the model is valid 0…400 only
  o.range_max_mm = 400;
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--range");
  o = {};
  o.start_mm = 100;
  o.spacing_mm = 20;
  o.count = 20;  // ends at 480 mm
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--start");
  o = {};
  o.spacing_mm = -5;
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--spacing");
}

TEST(Resample, ZeroAtReferenceAndUnidirectionalBacklash) {
  ResampleOptions o;
  o.spacing_mm = 20;
  o.zero_at_reference = true;
  o.bidirectional = false;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  EXPECT_FALSE(r.table.bidirectional);
  EXPECT_NEAR(r.table.forward_um.front(), 0, 1e-12);  // Px = 0 is the first point
  // Reverse error − forward error = 6 + (1·u … ) → mean over the points; correction sign: f − r > 0.
  double sum = 0;
  const auto axis = ExampleAxis();
  model::ThermalState cold;
  cold.use_thermal = false;
  for (double x : r.table.position_mm)
    sum += model::Predict(axis, x, Direction::kReverse, cold).total_um - model::Predict(axis, x, Direction::kForward, cold).total_um;
  EXPECT_NEAR(r.table.backlash_um, sum / r.table.size(), 1e-12);
  EXPECT_GT(r.table.backlash_um, 0);
  for (std::size_t i = 0; i < r.table.size(); ++i) EXPECT_EQ(r.table.forward_um[i], r.table.reverse_um[i]);
}

TEST(Resample, ZeroAtAReferenceOutsideTheTableIsAnError) {
  ResampleOptions o;
  o.range_min_mm = 100;
  o.range_max_mm = 400;
  o.zero_at_reference = true;  // Px = 0 is outside 100…400
  EXPECT_EQ(FieldOf([&] { ResampleModel(ExampleAxis(), o, "m.json"); }), "--zero-at-reference");
  o.reference_position_mm = 200;
  const auto r = ResampleModel(ExampleAxis(), o, "m.json");
  EXPECT_EQ(r.table.position_mm.front(), 100);
  EXPECT_NEAR(AppliedCorrectionUm(r.table, 200, Direction::kForward), 0, 1e-12);
}

TEST(Resample, MeasurementMeansPerTargetAndDirection) {
  measure::Measurement m;
  m.source = "meas.csv";
  m.SetMeta("axis", "Y");
  for (int run = 1; run <= 2; ++run)
    for (double x : {0.0, 50.0, 100.0}) {
      m.points.push_back({run, Direction::kForward, x, x / 10 + run, {}, {}, 0});
      m.points.push_back({run, Direction::kReverse, x, x / 10 - run, {}, {}, 0});
    }
  ResampleOptions o;
  const auto r = ResampleMeasurement(m, o);
  ASSERT_EQ(r.table.size(), 3u);
  EXPECT_EQ(r.table.axis, "Y");
  EXPECT_DOUBLE_EQ(r.table.forward_um[2], -(10 + 1.5));
  EXPECT_DOUBLE_EQ(r.table.reverse_um[1], -(5 - 1.5));
  o.spacing_mm = 25;
  const auto g = ResampleMeasurement(m, o);
  ASSERT_EQ(g.table.size(), 5u);
  EXPECT_DOUBLE_EQ(g.table.forward_um[1], -(2.5 + 1.5));
  ResampleOptions t;
  t.thermal.temperatures_c = {{"nut", 30}};
  EXPECT_EQ(FieldOf([&] { ResampleMeasurement(m, t); }), "--temp");
  m.points.pop_back();  // 100 mm reverse run 2 gone: still both directions
  m.points.erase(m.points.begin() + 5);
  EXPECT_EQ(FieldOf([&] { ResampleMeasurement(m, {}); }), "direction");
}

// A derived grid sits on round positions, not on a fitted reference point such as 10.335306 mm,
// and still covers the travel the source is valid for.
TEST(Resample, DerivedGridSitsOnRoundPositionsAndCoversTheTravel) {
  ResampleOptions o;
  o.spacing_mm = 5;
  // The travel 5.335306…840.335306 mm is a whole number of steps: a grid from a round start would
  // lose the last point, so the positions are rounded to 0.001 mm instead.
  auto g = MakeGrid(o, 5.335306, 840.335306, 10.335306, "m.json");
  ASSERT_EQ(g.size(), 168u);
  EXPECT_DOUBLE_EQ(g.front(), 5.335);
  EXPECT_DOUBLE_EQ(g.back(), 840.335);
  for (double x : g) EXPECT_NEAR(x * 1000, std::round(x * 1000), 1e-6) << x;
  // Where the travel allows, multiples of the spacing (as many points as from the travel's start).
  o.spacing_mm = 10;
  g = MakeGrid(o, 0.4, 800.2, 10.335306, "m.json");
  ASSERT_EQ(g.size(), 80u);
  EXPECT_DOUBLE_EQ(g.front(), 10);
  EXPECT_DOUBLE_EQ(g.back(), 800);
  // Whole millimetres when multiples of the spacing would lose a point.
  g = MakeGrid(o, 3.2, 803.7, 10.335306, "m.json");
  ASSERT_EQ(g.size(), 81u);
  EXPECT_DOUBLE_EQ(g.front(), 3.2);  // 0.1 mm: 4 mm would leave 80 points
  // A reference point given (or one the format counts from) is a grid point.
  o.reference_position_mm = 10.335306;
  EXPECT_DOUBLE_EQ(MakeGrid(o, 0.4, 800.2, 10.335306, "m.json").front(), 10.335306);
  o.reference_position_mm = ResampleOptions::kNaN;
  o.reference_on_grid = true;
  EXPECT_DOUBLE_EQ(MakeGrid(o, 0.4, 800.2, 10.335306, "m.json").front(), 10.335306);
}

}  // namespace
}  // namespace trueaxis::exporter
