// A model behind model::AxisErrorModel on a controller table's grid (issue 15): every value is
// minus the model's own error at the frozen temperatures, a data-driven thermal model (fitted here
// on a synthetic series) exports what it predicts, and what cannot be frozen is refused.
#include "trueaxis/export/resample_axis_model.hpp"

#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <random>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"
#include "trueaxis/thermal/model_fitting.hpp"
#include "trueaxis/thermal/thermal_axis_model.hpp"

namespace trueaxis::exporter {
namespace {

// Error depends on position, direction and both sensors, so a swapped sign, direction, sensor
// order or grid shows.
class FakeModel final : public model::AxisErrorModel {
 public:
  const std::string& Axis() const override { return axis_; }
  const std::vector<std::string>& Sensors() const override { return sensors_; }
  std::string Describe() const override { return "fake"; }
  double ErrorUm(double x, Direction d, std::span<const double> s, CoolantState, const model::AxisModelDynamics&) const override {
    return 0.01 * x * (s[0] - 20.0) + 0.2 * s[1] + (d == Direction::kForward ? 1.5 : -1.5);
  }

 private:
  std::string axis_ = "Y";
  std::vector<std::string> sensors_ = {"a", "b"};
};

ResampleOptions Options(std::vector<std::pair<std::string, double>> temps) {
  ResampleOptions o;
  o.range_min_mm = 0;
  o.range_max_mm = 500;
  o.spacing_mm = 50;
  o.thermal.temperatures_c = std::move(temps);
  return o;
}

InputError ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  return InputError("<none>", 0, "<no error>", "");
}

TEST(ResampleAxisModel, ValuesAreMinusTheModelErrorAtEveryGridPoint) {
  const FakeModel m;
  const auto r = ResampleAxisErrorModel(m, Options({{"b", 25}, {"a", 30}}), "fake.json");
  const auto& t = r.table;
  ASSERT_EQ(t.size(), 11u);
  EXPECT_EQ(t.axis, "Y");
  EXPECT_TRUE(t.bidirectional);
  const std::vector<double> s = {30, 25};
  model::AxisModelDynamics d;
  for (std::size_t i = 0; i < t.size(); ++i) {
    EXPECT_DOUBLE_EQ(t.position_mm[i], 50.0 * static_cast<double>(i));
    EXPECT_DOUBLE_EQ(t.forward_um[i], -m.ErrorUm(t.position_mm[i], Direction::kForward, s, CoolantState::kOff, d));
    EXPECT_DOUBLE_EQ(t.reverse_um[i], -m.ErrorUm(t.position_mm[i], Direction::kReverse, s, CoolantState::kOff, d));
  }
  // By hand at 500 mm forward: error 0.01·500·10 + 0.2·25 + 1.5 = 56.5 µm → correction −56.5 µm.
  EXPECT_DOUBLE_EQ(t.forward_um.back(), -56.5);
  EXPECT_FALSE(IsConstantAlongAxis(t));
}

TEST(ResampleAxisModel, UnidirectionalAndZeroAtReferenceUseTheSharedTail) {
  auto o = Options({{"a", 30}, {"b", 25}});
  o.bidirectional = false;
  o.zero_at_reference = true;
  o.reference_position_mm = 100;
  const auto r = ResampleAxisErrorModel(FakeModel(), o, "fake.json");
  EXPECT_FALSE(r.table.bidirectional);
  EXPECT_NEAR(r.table.backlash_um, -3.0, 1e-12);  // correction f − r = −(1.5 − (−1.5))
  EXPECT_NEAR(r.zero_shift_um, 0.0 - (0.01 * 100 * 10 + 5.0), 1e-12);  // mean curve at 100 mm
  EXPECT_NEAR(r.table.forward_um[2], 0.0, 1e-12);
}

TEST(ResampleAxisModel, EverySensorMustBeGivenAndNoOther) {
  const FakeModel m;
  const auto missing = ErrorOf([&] { ResampleAxisErrorModel(m, Options({{"a", 30}}), "fake.json"); });
  EXPECT_EQ(missing.field(), "--temp");
  EXPECT_NE(missing.message().find("missing sensor 'b'"), std::string::npos) << missing.message();
  const auto unknown = ErrorOf([&] { ResampleAxisErrorModel(m, Options({{"a", 30}, {"b", 25}, {"c", 20}}), "fake.json"); });
  EXPECT_EQ(unknown.field(), "--temp");
  EXPECT_NE(unknown.message().find("'c'"), std::string::npos) << unknown.message();
  EXPECT_NE(unknown.message().find("a, b"), std::string::npos) << unknown.message();  // what the model reads
  EXPECT_EQ(unknown.source(), "fake.json");
}

TEST(ResampleAxisModel, RangeIsRequired) {
  auto o = Options({{"a", 30}, {"b", 25}});
  o.range_min_mm = o.range_max_mm = ResampleOptions::kNaN;
  EXPECT_EQ(ErrorOf([&] { ResampleAxisErrorModel(FakeModel(), o, "fake.json"); }).field(), "--range");
  o = Options({{"a", 30}, {"b", 25}});
  o.spacing_mm = 1;  // 501 points > 256
  EXPECT_EQ(ErrorOf([&] { ResampleAxisErrorModel(FakeModel(), o, "fake.json"); }).field(), "--spacing");
}

TEST(ResampleAxisModel, AModelThatKnowsItsPositionsIsNotExtrapolated) {
  const AxisModelValidity trained{0, 400};
  EXPECT_EQ(ErrorOf([&] { ResampleAxisErrorModel(FakeModel(), Options({{"a", 30}, {"b", 25}}), "fake.json", trained); }).field(),
            "--range");
  auto o = Options({{"a", 30}, {"b", 25}});
  o.range_max_mm = 400;
  EXPECT_EQ(ResampleAxisErrorModel(FakeModel(), o, "fake.json", trained).table.position_mm.back(), 400);
}

// 8 h, 30 s samples, spindle blocks 0/2500/0/3500 rpm: s0 heats with the spindle, s1 swings slowly,
// the error follows s0's lagged rise (so lags and intervals matter).
thermal::ThermalSeries SyntheticSeries(unsigned seed) {
  thermal::ThermalSeries s;
  s.source = "synthetic";
  s.has_time = true;
  const int rows = 8 * 120;
  s.temperature_names = {"s0", "s1"};
  s.error_names = {"e"};
  s.temperatures_c = Eigen::MatrixXd::Zero(rows, 2);
  s.errors_um = Eigen::MatrixXd::Zero(rows, 1);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  double t0 = 22, slow = 22;
  for (int r = 0; r < rows; ++r) {
    const double h = r * 30.0 / 3600;
    s.time_s.push_back(r * 30.0);
    s.source_line.push_back(r + 2);
    const double rpm = h < 2 ? 0 : h < 4 ? 2500 : h < 6 ? 0 : 3500;
    t0 += (22 + rpm / 500.0 - t0) * 30.0 / 2400.0;
    slow += (t0 - slow) * 30.0 / 1800.0;
    s.temperatures_c(r, 0) = t0 + noise(rng);
    s.temperatures_c(r, 1) = 21 + 0.4 * std::sin(h) + noise(rng);
    s.errors_um(r, 0) = 2.0 * (t0 - 22) + 1.5 * (slow - 22) + noise(rng);
  }
  return s;
}

// The fitted model's own prediction for one sample of temperatures (InputSensors() order; a
// lagged input takes its sensor's temperature as settled).
double ModelErrorUm(const thermal::ThermalErrorModel& m, const std::map<std::string, double>& temps, double x_mm,
                    thermal::ThermalInterval interval) {
  std::vector<double> in;
  for (const auto& name : m.InputSensors()) {
    std::string base = name;
    double tau = 0;
    thermal::ParseLaggedName(name, &base, &tau);
    in.push_back(temps.at(base));
  }
  std::vector<double> out(m.Channels().size());
  m.Predict(thermal::ThermalSample{in, x_mm, interval}, out);
  return out[0];
}

void ExpectTableIsTheFittedPrediction(const thermal::ThermalSeries& s, thermal::ModelKind kind) {
  thermal::ThermalFitOptions fo;
  fo.kind = kind;
  std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::FitThermalModel(s, fo);
  const thermal::ThermalAxisModel axis(fitted, "e", "Z", "fitted.json");
  const std::map<std::string, double> temps = {{"s0", 31.0}, {"s1", 21.5}};
  std::vector<std::pair<std::string, double>> given;
  for (const auto& name : axis.Sensors()) given.emplace_back(name, temps.at(name));
  const auto r = ResampleAxisErrorModel(axis, Options(given), "fitted.json");
  // Hysteresis: the all-data (start-up) model; the others ignore the interval.
  const double expected = -ModelErrorUm(*fitted, temps, 0.0, thermal::ThermalInterval::kStartUp);
  EXPECT_GT(std::abs(expected), 5.0) << "the synthetic model should predict a sizeable error at 31 °C";
  if (fitted->UsesInterval())  // the test tells the all-data model from a sub-model
    EXPECT_GT(std::abs(ModelErrorUm(*fitted, temps, 0.0, thermal::ThermalInterval::kHeating) + expected), 1e-3);
  for (std::size_t i = 0; i < r.table.size(); ++i) {
    EXPECT_NEAR(r.table.forward_um[i], expected, 1e-9) << i;
    EXPECT_NEAR(r.table.reverse_um[i], expected, 1e-9) << i;
  }
  EXPECT_TRUE(IsConstantAlongAxis(r.table));  // these models do not use the position
}

TEST(ResampleAxisModel, RidgeModelExportsItsOwnPrediction) {
  ExpectTableIsTheFittedPrediction(SyntheticSeries(5), thermal::ModelKind::kRidge);
}

TEST(ResampleAxisModel, LaggedInputsTakeTheGivenTemperatureAsSettled) {
  thermal::ThermalSeries lagged = thermal::AddLaggedTemperatures(SyntheticSeries(6), {1800.0});
  thermal::ThermalFitOptions fo;
  fo.linear.selection.method = thermal::SelectionMethod::kAll;
  std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::FitThermalModel(lagged, fo);
  bool has_lag = false;
  for (const auto& n : fitted->InputSensors()) has_lag = has_lag || n.find("@lag") != std::string::npos;
  ASSERT_TRUE(has_lag);
  const thermal::ThermalAxisModel axis(fitted, "e", "Z", "fitted.json");
  EXPECT_EQ(axis.Sensors().size(), 2u);  // only the real sensors are asked for
  const auto r = ResampleAxisErrorModel(axis, Options({{"s0", 31.0}, {"s1", 21.5}}), "fitted.json");
  const double expected = -ModelErrorUm(*fitted, {{"s0", 31.0}, {"s1", 21.5}}, 0.0, thermal::ThermalInterval::kSteady);
  EXPECT_NEAR(r.table.forward_um.front(), expected, 1e-9);
}

TEST(ResampleAxisModel, HysteresisModelExportsItsAllDataPrediction) {
  ExpectTableIsTheFittedPrediction(SyntheticSeries(7), thermal::ModelKind::kHysteresis);
}

}  // namespace
}  // namespace trueaxis::exporter
