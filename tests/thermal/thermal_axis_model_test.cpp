// A data-driven thermal model deployed on an axis through model::AxisErrorModel (the interface the
// compensator binds): the adapter predicts exactly what the model predicts for a row, and refuses
// what it cannot deploy.
#include "trueaxis/thermal/thermal_axis_model.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/model_fitting.hpp"

namespace trueaxis::thermal {
namespace {

// Feeds the recording row by row as the compensator would (Advance, then ErrorUm with the
// Sensors() readings) and checks each row against the fit's own prediction for the recording.
// Returns how often each interval was used.
std::array<int, 4> ExpectAdapterFollowsTheModel(const ThermalSeries& s, std::shared_ptr<const ThermalErrorModel> fitted) {
  const ThermalAxisModel axis(fitted, "e", "Z", "fitted");
  EXPECT_EQ(axis.Axis(), "Z");
  for (const auto& name : axis.Sensors()) {
    std::string base;
    double tau = 0;
    EXPECT_FALSE(ParseLaggedName(name, &base, &tau)) << name << ": the compensator has no such channel";
  }
  const Eigen::MatrixXd predicted = PredictSeries(*fitted, s);
  std::vector<ThermalInterval> intervals(static_cast<std::size_t>(s.Rows()), ThermalInterval::kSteady);
  if (fitted->UsesInterval()) intervals = fitted->ClassifyRows(WithLaggedInputs(s, fitted->InputSensors()));
  model::AxisModelDynamics d;
  axis.ResetDynamics(d);
  std::array<int, 4> seen{};
  for (int r = 0; r < s.temperatures_c.rows(); ++r) {
    std::vector<double> inputs;
    for (const auto& name : axis.Sensors()) {
      const auto it = std::find(s.temperature_names.begin(), s.temperature_names.end(), name);
      EXPECT_NE(it, s.temperature_names.end()) << name;
      inputs.push_back(s.temperatures_c(r, static_cast<int>(it - s.temperature_names.begin())));
    }
    axis.Advance(d, s.time_s[static_cast<std::size_t>(r)], inputs);
    const ThermalInterval got = axis.Interval(d);
    EXPECT_EQ(got, intervals[static_cast<std::size_t>(r)]) << "row " << r;
    ++seen[static_cast<std::size_t>(got)];
    EXPECT_NEAR(axis.ErrorUm(0.0, Direction::kForward, inputs, CoolantState::kOff, d), predicted(r, 0), 1e-6) << "row " << r;
  }
  return seen;
}

void ExpectAdapterMatchesTheModel(ModelKind kind) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  o.kind = kind;
  o.network.seed = 3;
  ExpectAdapterFollowsTheModel(s, FitThermalModel(s, o));
}

TEST(ThermalAxisModel, RidgeModelPredictsThroughTheAdapterExactly) { ExpectAdapterMatchesTheModel(ModelKind::kRidge); }

TEST(ThermalAxisModel, PsoBpNetworkPredictsThroughTheAdapterExactly) { ExpectAdapterMatchesTheModel(ModelKind::kPsoBp); }

TEST(ThermalAxisModel, RefusesAnUnknownChannel) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  std::shared_ptr<const ThermalErrorModel> ridge = FitThermalModel(s, o);
  try {
    ThermalAxisModel(ridge, "x_um", "X", "m.json");
    FAIL() << "accepted an unknown channel";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x_um"), std::string::npos) << e.what();
  }
}

// The seed-001 hysteresis model on an axis: fed sample by sample as the compensator feeds it, its
// interval and its prediction are the fit's own for every row of the recording.
TEST(ThermalAxisModel, HysteresisModelFollowsTheIntervalSampleBySample) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  o.kind = ModelKind::kHysteresis;
  std::shared_ptr<const ThermalErrorModel> fitted = FitThermalModel(s, o);
  const auto seen = ExpectAdapterFollowsTheModel(s, fitted);
  EXPECT_GT(seen[static_cast<int>(ThermalInterval::kHeating)], 0);
  EXPECT_GT(seen[static_cast<int>(ThermalInterval::kCooling)], 0);
  // A restart (lost sensor, new model) predicts as at start-up: the all-data model.
  const ThermalAxisModel axis(fitted, "e", "Z", "fitted");
  model::AxisModelDynamics d;
  axis.ResetDynamics(d);
  EXPECT_EQ(axis.Interval(d), ThermalInterval::kStartUp);
}

// Lagged inputs ("t4@lag1800s") are computed by the adapter from their sensor with the fit's lag.
TEST(ThermalAxisModel, LaggedInputsAreComputedFromTheirSensorsCycleByCycle) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  o.kind = ModelKind::kRidge;
  const ThermalSeries lagged = AddLaggedTemperatures(s, {600.0, 1800.0});
  o.linear.selection.method = SelectionMethod::kAll;  // every raw and lagged column
  std::shared_ptr<const ThermalErrorModel> fitted = FitThermalModel(lagged, o);
  bool has_lag = false;
  for (const auto& n : fitted->InputSensors()) has_lag = has_lag || n.find("@lag") != std::string::npos;
  ASSERT_TRUE(has_lag);
  ExpectAdapterFollowsTheModel(s, fitted);
}

}  // namespace
}  // namespace trueaxis::thermal
