// The room temperatures the model was fitted on (AxisModel::ambient_fitted_range_c; issue 10:
// never a silent wrong answer): outside them the ρ term is extrapolated — flagged, not held.
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::model {
namespace {

using testing::SyntheticMachine;
using ::testing::HasSubstr;

AxisModel RoomAxis() {
  AxisModel a = testing::OneKeyAxis(-0.006);
  a.rho_um_per_mm_per_c = -0.0115;
  a.ambient_fitted_range_c = {18.5, 24.0};
  return a;
}

TEST(AmbientFittedRange, PredictFlagsARoomOutsideItButDoesNotHoldIt) {
  const AxisModel a = RoomAxis();
  const std::vector<double> nut{20.0};
  ThermalState st;
  st.key_temp_c = nut;
  for (double room : {18.5, 21.0, 24.0}) {  // the ends belong to the range
    st.ambient_c = room;
    const auto p = Predict(a, 400, Direction::kForward, st);
    EXPECT_FALSE(p.ambient_extrapolated) << room;
    EXPECT_FALSE(p.tan_beta_limited) << room;
  }
  // 17 °C, 1.5 °C colder than any fitted state: the ρ term is the model's own, extrapolated
  // (a soaked machine in a colder room really is shorter), and the prediction says so.
  st.ambient_c = 17.0;
  const auto cold = Predict(a, 400, Direction::kForward, st);
  EXPECT_TRUE(cold.ambient_extrapolated);
  EXPECT_NEAR(cold.ambient_um, -0.0115 * (17.0 - 20.0) * (0 - 400), 1e-9);
  st.ambient_c = 26.0;
  EXPECT_TRUE(Predict(a, 400, Direction::kForward, st).ambient_extrapolated);
  // No ambient reading: no ρ term, nothing to flag.
  st.ambient_c = std::nan("");
  EXPECT_FALSE(Predict(a, 400, Direction::kForward, st).ambient_extrapolated);
  // A model file written before the range was recorded (NaN): never flagged.
  AxisModel old = RoomAxis();
  old.ambient_fitted_range_c = {std::nan(""), std::nan("")};
  st.ambient_c = 5.0;
  EXPECT_FALSE(Predict(old, 400, Direction::kForward, st).ambient_extrapolated);
}

TEST(AmbientFittedRange, TheFitRecordsTheLowestAndHighestRoomReading) {
  SyntheticMachine sm;
  auto states = sm.DefaultStates();
  states.push_back({"ambient-17", 0, 0, 0, -3.0});
  const auto fit_states = sm.MakeStates(states);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& s : fit_states) {
    const auto idx = *s.measurement.SensorIndex("ambient");
    for (const auto& p : s.measurement.points) lo = std::min(lo, p.temperatures_c[idx]), hi = std::max(hi, p.temperatures_c[idx]);
  }
  FitOptions o;
  o.key_sensors = {"nut", "bearing"};
  const auto r = FitCompositeModel(fit_states, o);
  const auto& a = r.model.axes.at(0);
  ASSERT_EQ(a.ambient_sensor, "ambient");
  EXPECT_DOUBLE_EQ(a.ambient_fitted_range_c[0], lo);
  EXPECT_DOUBLE_EQ(a.ambient_fitted_range_c[1], hi);
  EXPECT_NEAR(lo, 17.0, 0.1);  // baseline 20 − 3 (plus the sensor's scatter)
  EXPECT_NEAR(hi, 24.0, 0.1);  // the "ambient-24" state
}

TEST(AmbientFittedRange, ModelFileRoundTripOlderFileAndBadValues) {
  CompositeModel m;
  m.axes.push_back(RoomAxis());
  const auto j = ModelToJson(m);
  ASSERT_TRUE(j["axes"][0].contains("ambient_fitted_range_c"));
  const auto back = ModelFromJson(j, "m.json");
  EXPECT_EQ(back.axes[0].ambient_fitted_range_c, (std::array<double, 2>{18.5, 24.0}));
  auto old = j;
  old["axes"][0].erase("ambient_fitted_range_c");
  EXPECT_TRUE(std::isnan(ModelFromJson(old, "m.json").axes[0].ambient_fitted_range_c[0]));
  auto expect_refused = [](const nlohmann::json& bad, const std::string& why) {
    try {
      ModelFromJson(bad, "m.json");
      ADD_FAILURE() << "accepted: " << why;
    } catch (const InputError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr("ambient_fitted_range_c")) << why;
    }
  };
  auto bad = j;
  bad["axes"][0]["ambient_fitted_range_c"] = {24.0, 18.5};
  expect_refused(bad, "low above high");
  bad["axes"][0]["ambient_fitted_range_c"] = {18.5};
  expect_refused(bad, "one number");
  bad["axes"][0]["ambient_fitted_range_c"] = {"cold", 24.0};
  expect_refused(bad, "not a number");
  bad = j;
  bad["axes"][0].erase("ambient_sensor");
  bad["axes"][0]["key_temperature_rise"] = "from_baseline";
  expect_refused(bad, "a range without an ambient sensor");
}

}  // namespace
}  // namespace trueaxis::model
