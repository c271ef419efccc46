// A data-driven thermal model deployed on an axis through model::AxisErrorModel (the interface the
// compensator binds): the adapter predicts exactly what the model predicts for a row, and refuses
// what it cannot deploy.
#include "trueaxis/thermal/thermal_axis_model.hpp"

#include <gtest/gtest.h>

#include "test_util.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/model_fitting.hpp"

namespace trueaxis::thermal {
namespace {

void ExpectAdapterMatchesTheModel(ModelKind kind) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  o.kind = kind;
  o.network.seed = 3;
  std::shared_ptr<const ThermalErrorModel> fitted = FitThermalModel(s, o);
  const ThermalAxisModel axis(fitted, "e", "Z", "fitted");
  EXPECT_EQ(axis.Axis(), "Z");
  EXPECT_EQ(axis.Sensors(), fitted->InputSensors());
  const Eigen::MatrixXd predicted = PredictSeries(*fitted, s);
  for (int r = 0; r < s.temperatures_c.rows(); r += 97) {
    std::vector<double> inputs;
    for (const auto& name : axis.Sensors()) {
      const auto it = std::find(s.temperature_names.begin(), s.temperature_names.end(), name);
      inputs.push_back(s.temperatures_c(r, static_cast<int>(it - s.temperature_names.begin())));
    }
    EXPECT_DOUBLE_EQ(axis.ErrorUm(0.0, Direction::kForward, inputs, CoolantState::kOff), predicted(r, 0)) << "row " << r;
  }
}

TEST(ThermalAxisModel, RidgeModelPredictsThroughTheAdapterExactly) { ExpectAdapterMatchesTheModel(ModelKind::kRidge); }

TEST(ThermalAxisModel, PsoBpNetworkPredictsThroughTheAdapterExactly) { ExpectAdapterMatchesTheModel(ModelKind::kPsoBp); }

TEST(ThermalAxisModel, RefusesAnUnknownChannelAndTheIntervalModel) {
  const ThermalSeries s = testing::MakeSpindleBlockSeries(7);
  ThermalFitOptions o;
  std::shared_ptr<const ThermalErrorModel> ridge = FitThermalModel(s, o);
  EXPECT_THROW(ThermalAxisModel(ridge, "x_um", "X", "m.json"), InputError);
  o.kind = ModelKind::kHysteresis;
  std::shared_ptr<const ThermalErrorModel> hysteresis = FitThermalModel(s, o);
  try {
    ThermalAxisModel(hysteresis, "e", "X", "m.json");
    FAIL() << "accepted a hysteresis model";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("interval"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace trueaxis::thermal
