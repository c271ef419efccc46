// Lagged temperatures as inputs: the filter, the columns, and a model that needs them.
#include <cmath>

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/model_fitting.hpp"

namespace trueaxis::thermal {
namespace {

TEST(InputLagFilter, FirstOrderStepResponse) {
  InputLagFilter f(600);
  EXPECT_DOUBLE_EQ(f.Push(0, 20), 20);  // starts at the reading
  double v = 20;
  for (int s = 1; s <= 600; ++s) v = f.Push(s, 30);  // step to 30 °C, 1 s samples, one τ
  EXPECT_NEAR(v, 20 + 10 * (1 - std::exp(-1.0)), 1e-9);
  f.Reset();
  EXPECT_DOUBLE_EQ(f.Push(700, 25), 25);
}

TEST(LaggedNames, RoundTrip) {
  std::string sensor;
  double tau = 0;
  EXPECT_EQ(LaggedName("t4", 1800), "t4@lag1800s");
  ASSERT_TRUE(ParseLaggedName("x_nut@lag5400s", &sensor, &tau));
  EXPECT_EQ(sensor, "x_nut");
  EXPECT_EQ(tau, 5400);
  EXPECT_FALSE(ParseLaggedName("t4", nullptr, nullptr));
  EXPECT_FALSE(ParseLaggedName("t4@lags", nullptr, nullptr));
  EXPECT_FALSE(ParseLaggedName("t4@lag-5s", nullptr, nullptr));
}

TEST(LaggedColumns, AddedPerSensorAndTauRestartingAtEachExperiment) {
  ThermalSeries a = testing::MakeSeries(400, 2), b = testing::MakeSeries(400, 2);  // 100 min each
  a.source = "a", b.source = "b";
  a.temperatures_c.setConstant(20);
  b.temperatures_c.setConstant(30);
  const ThermalSeries j = ConcatenateExperiments({a, b}, nullptr);
  std::vector<double> skipped;
  const ThermalSeries lagged = AddLaggedTemperatures(j, {600, 1800, 100000}, &skipped);
  ASSERT_EQ(lagged.temperature_names.size(), 2u + 4u);
  EXPECT_EQ(lagged.temperature_names[2], "s0@lag600s");
  EXPECT_EQ(skipped, std::vector<double>{100000});
  // The second experiment starts at its own reading (30 °C), not at the first one's lag.
  EXPECT_DOUBLE_EQ(lagged.temperatures_c(400, 2), 30.0);
  EXPECT_THROW(AddLaggedTemperatures(j, {-5}), InputError);
}

// The error follows a 30-min lag of the sensor (a structure behind its surface sensor): with the
// lagged inputs offered, the model finds it; with the raw reading only, it cannot.
TEST(LaggedColumns, AModelOnALaggedInputPredictsFromAPlainRecording) {
  ThermalSeries s = testing::MakeSeries(8 * 240, 1);
  InputLagFilter truth(1800);
  for (int r = 0; r < s.Rows(); ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    s.temperatures_c(r, 0) = 20 + (std::fmod(h, 4) < 2 ? 4.0 : 0.0);  // spindle on / off every 2 h
    s.errors_um(r, 0) = 3.0 * (truth.Push(s.time_s[static_cast<std::size_t>(r)], s.temperatures_c(r, 0)) - 20);
  }
  ThermalFitOptions o;
  o.kind = ModelKind::kRidge;
  o.ridge_lambda = 1e-9;
  o.linear.selection.max_sensors = 1;
  auto rmse = [&](const ThermalErrorModel& m) {
    return std::sqrt((s.errors_um - PredictSeries(m, s)).squaredNorm() / static_cast<double>(s.Rows()));
  };
  const auto raw = FitThermalModel(s, o);
  const auto lagged = FitThermalModel(AddLaggedTemperatures(s, {600, 1800, 5400}), o);
  EXPECT_EQ(lagged->InputSensors(), std::vector<std::string>{"s0@lag1800s"});
  // PredictSeries on the plain series computes the lag itself.
  EXPECT_LT(rmse(*lagged), 1e-3);
  EXPECT_GT(rmse(*raw), 1.0);
  ThermalSeries no_sensor = s;
  no_sensor.temperature_names = {"other"};
  EXPECT_THROW(PredictSeries(*lagged, no_sensor), InputError);
}

}  // namespace
}  // namespace trueaxis::thermal
