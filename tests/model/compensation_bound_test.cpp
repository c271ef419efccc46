// The bound derived from a fitted model, pinned on an axis whose largest correction is known by hand.
#include "trueaxis/model/compensation_bound.hpp"

#include <gtest/gtest.h>

namespace trueaxis::model {
namespace {

// Er = 0; tanβ = k·ΔT_nut with k = 0.01 µm/mm/°C, Px = 0, travel 0…1000 mm. The fit saw the nut at
// 20…30 °C (baseline 20); the envelope adds 5 °C: ΔT = 15 °C at the far end, |error| = 0.01·15·1000.
AxisModel ThermalOnlyAxis() {
  AxisModel a;
  a.axis = "X";
  a.reference_position_mm = 0;
  a.key_sensors = {"x_nut"};
  a.baseline_temp_c = {20};
  a.key_fitted_range_c = {{20, 30}};
  for (auto& d : a.directions) {
    d.geometric.center_mm = 500;
    d.geometric.half_span_mm = 500;
    d.geometric.coefficients_um = {0};
    d.thermal = {{CoolantState::kOff, {0.01}, 0}};
  }
  return a;
}

TEST(CompensationBound, LargestCorrectionOverTravelAndTemperatureWithHeadroom) {
  const auto b = DeriveCompensationBound(ThermalOnlyAxis());
  EXPECT_NEAR(b.model_max_um, 150.0, 1e-9);
  EXPECT_DOUBLE_EQ(b.bound_um, 190.0);  // 150 × 1.25 = 187.5, rounded up to 5 µm
  EXPECT_FALSE(b.limited_by_controller);
}

// A fallback (used when the key sensor is lost) asking for more sets the bound: 0.02 on a bearing
// seen at 20…25 °C (+5): 0.02·10·1000 = 200 µm. One asking for less leaves it.
TEST(CompensationBound, AFallbackModelsCorrectionsMustPassToo) {
  AxisModel a = ThermalOnlyAxis();
  AxisModel f = ThermalOnlyAxis();
  f.key_sensors = {"x_bearing"};
  f.key_fitted_range_c = {{20, 25}};
  for (auto& d : f.directions) d.thermal = {{CoolantState::kOff, {0.02}, 0}};
  a.fallbacks.push_back(f);
  const auto b = DeriveCompensationBound(a);
  EXPECT_NEAR(b.model_max_um, 200.0, 1e-9);
  EXPECT_DOUBLE_EQ(b.bound_um, 250.0);
  for (auto& d : a.fallbacks[0].directions) d.thermal = {{CoolantState::kOff, {0.005}, 0}};
  EXPECT_NEAR(DeriveCompensationBound(a).model_max_um, 150.0, 1e-9);
}

TEST(CompensationBound, TheControllerLimitCapsItAndSaysSo) {
  CompensationBoundOptions o;
  o.controller_limit_um = 100;
  const auto b = DeriveCompensationBound(ThermalOnlyAxis(), o);
  EXPECT_DOUBLE_EQ(b.bound_um, 100.0);
  EXPECT_TRUE(b.limited_by_controller);
  EXPECT_NE(b.BriefReport().find("LIMITED"), std::string::npos);
}

TEST(CompensationBound, GeometricOnlyAndNoRecordedRange) {
  AxisModel a = ThermalOnlyAxis();
  a.key_fitted_range_c.clear();  // an older model file: a generous +15 °C (+5) rise is assumed
  const auto b = DeriveCompensationBound(a);
  EXPECT_NEAR(b.model_max_um, 0.01 * 20 * 1000, 1e-9);
  AxisModel g = ThermalOnlyAxis();
  g.key_sensors.clear();
  g.baseline_temp_c.clear();
  g.key_fitted_range_c.clear();
  for (auto& d : g.directions) d.thermal.clear(), d.geometric.coefficients_um = {-3};
  const auto small = DeriveCompensationBound(g);
  EXPECT_NEAR(small.model_max_um, 3.0, 1e-9);
  EXPECT_DOUBLE_EQ(small.bound_um, 10.0);  // never below min_bound_um
}

}  // namespace
}  // namespace trueaxis::model
