#include "trueaxis/model/composite_model.hpp"

#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::model {
namespace {

AxisModel ExampleAxis() {
  AxisModel a;
  a.axis = "X";
  a.reference_position_mm = 0;
  a.key_sensors = {"nut", "bearing"};
  a.baseline_temp_c = {20, 20};
  a.ambient_sensor = "ambient";
  a.ambient_baseline_c = 20;
  a.rho_um_per_mm_per_c = 0.0115;
  auto& fwd = a.directions[0];
  fwd.geometric.kind = GeometricError::Kind::kPolynomial;
  fwd.geometric.center_mm = 250;
  fwd.geometric.half_span_mm = 250;
  fwd.geometric.coefficients_um = {1.0, 2.0, 0.5};
  fwd.thermal = {{CoolantState::kOff, {-0.01, -0.004}, 0}, {CoolantState::kFlood, {-0.005, -0.002}, 0}};
  auto& rev = a.directions[1];
  rev.geometric.kind = GeometricError::Kind::kTable;
  rev.geometric.table_position_mm = {0, 100, 200};
  rev.geometric.table_error_um = {3, 5, 4};
  rev.thermal = {{CoolantState::kOff, {-0.01, -0.004}, 0}};
  return a;
}

TEST(CompositeModel, PolynomialIsEvaluatedInNormalisedCoordinate) {
  auto a = ExampleAxis();
  // u = (500-250)/250 = 1 -> 1 + 2 + 0.5
  EXPECT_DOUBLE_EQ(a.directions[0].geometric.Evaluate(500), 3.5);
  EXPECT_DOUBLE_EQ(a.directions[0].geometric.Evaluate(250), 1.0);
}

TEST(CompositeModel, TableInterpolatesLinearlyAndHoldsEnds) {
  auto a = ExampleAxis();
  const auto& g = a.directions[1].geometric;
  EXPECT_DOUBLE_EQ(g.Evaluate(50), 4.0);
  EXPECT_DOUBLE_EQ(g.Evaluate(150), 4.5);
  EXPECT_DOUBLE_EQ(g.Evaluate(-10), 3.0);
  EXPECT_DOUBLE_EQ(g.Evaluate(999), 4.0);
}

TEST(CompositeModel, ThermalPartIsTanBetaTimesLeverAboutReference) {
  auto a = ExampleAxis();
  const double temps[] = {25, 22};  // rises 5 and 2
  ThermalState s{temps, 20.0, CoolantState::kOff, true};
  auto p = Predict(a, 400, Direction::kForward, s);
  const double tan_beta = -0.01 * 5 - 0.004 * 2;
  EXPECT_DOUBLE_EQ(p.tan_beta_um_per_mm, tan_beta);
  EXPECT_DOUBLE_EQ(p.thermal_um, tan_beta * (0 - 400));
  EXPECT_DOUBLE_EQ(p.ambient_um, 0);
  EXPECT_DOUBLE_EQ(p.total_um, p.geometric_um + p.thermal_um);
  EXPECT_DOUBLE_EQ(CorrectionUm(p), -p.total_um);
}

TEST(CompositeModel, CoolantStateSelectsGainsAndFallsBackToOff) {
  auto a = ExampleAxis();
  const double temps[] = {25, 22};
  auto flood = Predict(a, 400, Direction::kForward, {temps, NAN, CoolantState::kFlood, true});
  EXPECT_DOUBLE_EQ(flood.tan_beta_um_per_mm, -0.005 * 5 - 0.002 * 2);
  auto mist = Predict(a, 400, Direction::kForward, {temps, NAN, CoolantState::kMist, true});
  EXPECT_DOUBLE_EQ(mist.tan_beta_um_per_mm, -0.01 * 5 - 0.004 * 2);  // no mist entry: "off" gains
}

TEST(CompositeModel, AmbientAdjustmentIsRhoDeltaTLever) {
  auto a = ExampleAxis();
  const double temps[] = {20, 20};
  auto p = Predict(a, 300, Direction::kForward, {temps, 23.0, CoolantState::kOff, true});
  EXPECT_NEAR(p.ambient_um, 0.0115 * 3 * (0 - 300), 1e-12);
}

TEST(CompositeModel, NanTemperatureOrThermalOffGivesGeometricOnly) {
  auto a = ExampleAxis();
  const double temps[] = {NAN, 22};
  auto p = Predict(a, 300, Direction::kReverse, {temps, NAN, CoolantState::kOff, true});
  EXPECT_DOUBLE_EQ(p.thermal_um, 0);
  EXPECT_DOUBLE_EQ(p.total_um, a.directions[1].geometric.Evaluate(300));
  const double ok[] = {30, 30};
  auto q = Predict(a, 300, Direction::kReverse, {ok, 30.0, CoolantState::kOff, false});
  EXPECT_DOUBLE_EQ(q.total_um, q.geometric_um);
}

// Machines that load the same model file share one parsed model; changed bytes are read anew.
TEST(ModelJson, SharedReadParsesTheSameFileOnce) {
  CompositeModel m;
  m.machine = "VMC";
  m.axes = {ExampleAxis()};
  const std::string path = (std::filesystem::temp_directory_path() / "trueaxis_model_shared.json").string();
  WriteModelFile(m, path);
  const auto first = ReadSharedModelFile(path);
  const auto second = ReadSharedModelFile(path);
  EXPECT_EQ(first.get(), second.get());
  EXPECT_EQ(first->machine, "VMC");
  m.machine = "HMC";  // the file changes: its new content, not the shared old one
  WriteModelFile(m, path);
  const auto third = ReadSharedModelFile(path);
  EXPECT_NE(third.get(), first.get());
  EXPECT_EQ(third->machine, "HMC");
  EXPECT_EQ(first->machine, "VMC");  // a model in use never changes under its holder
  std::filesystem::remove(path);
  EXPECT_THROW(ReadSharedModelFile(path), InputError);  // gone: an error, never the cached model
}

TEST(ModelJson, RoundTripPreservesPredictions) {
  CompositeModel m;
  m.machine = "VMC";
  m.sources = {{"cold.csv", "abc", "cold"}};
  m.axes = {ExampleAxis()};
  const std::string path = (std::filesystem::temp_directory_path() / "trueaxis_model_rt.json").string();
  WriteModelFile(m, path);
  auto back = ReadModelFile(path);
  ASSERT_EQ(back.axes.size(), 1u);
  const double temps[] = {27, 24};
  for (double x : {0.0, 123.4, 480.0})
    for (auto d : {Direction::kForward, Direction::kReverse}) {
      ThermalState s{temps, 21.5, CoolantState::kFlood, true};
      EXPECT_DOUBLE_EQ(Predict(back.axes[0], x, d, s).total_um, Predict(m.axes[0], x, d, s).total_um);
    }
  EXPECT_EQ(back.sources[0].sha256, "abc");
}

TEST(ModelJson, BadFieldsAreNamedByPath) {
  CompositeModel m;
  m.axes = {ExampleAxis()};
  auto j = ModelToJson(m);
  j["axes"][0]["reverse"]["geometric"]["position_mm"] = {0, 200, 100};
  try {
    ModelFromJson(j, "m.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "m.json: field 'axes[0].reverse.geometric.position_mm[2]': positions must be strictly ascending");
  }
  j = ModelToJson(m);
  j["axes"][0]["forward"]["thermal"][0]["k_um_per_mm_per_c"] = {1.0};
  EXPECT_THROW(ModelFromJson(j, "m.json"), InputError);
  j = ModelToJson(m);
  j.erase("axes");
  EXPECT_THROW(ModelFromJson(j, "m.json"), InputError);
}

AxisModel ExampleFallback() {
  AxisModel f = ExampleAxis();
  f.key_sensors = {"bearing", "motor"};  // without the nut; the fit may take another sensor in
  f.baseline_temp_c = {20, 21};
  for (auto& d : f.directions) d.thermal = {{CoolantState::kOff, {-0.02, 0.003}, 0}};
  return f;
}

TEST(ModelJson, FallbackModelsRoundTripInOrder) {
  CompositeModel m;
  m.axes = {ExampleAxis()};
  m.axes[0].fallbacks = {ExampleFallback(), ExampleFallback()};
  m.axes[0].fallbacks[1].key_sensors = {"nut"};
  m.axes[0].fallbacks[1].baseline_temp_c = {20};
  for (auto& d : m.axes[0].fallbacks[1].directions) d.thermal = {{CoolantState::kOff, {-0.012}, 0}};
  m.axes[0].fallbacks[0].replaces = "nut";
  const auto back = ModelFromJson(ModelToJson(m), "m.json");
  ASSERT_EQ(back.axes[0].fallbacks.size(), 2u);
  EXPECT_EQ(back.axes[0].fallbacks[0].replaces, "nut");
  EXPECT_EQ(back.axes[0].fallbacks[1].replaces, "");  // not stated (files before it): not averaged
  EXPECT_FALSE(ModelToJson(m)["axes"][0]["fallbacks"][1].contains("replaces"));
  EXPECT_EQ(back.axes[0].fallbacks[0].key_sensors, (std::vector<std::string>{"bearing", "motor"}));
  EXPECT_EQ(back.axes[0].fallbacks[1].key_sensors, (std::vector<std::string>{"nut"}));
  const double temps[] = {27, 24};
  ThermalState s{temps, 21.5, CoolantState::kOff, true};
  EXPECT_DOUBLE_EQ(Predict(back.axes[0].fallbacks[0], 300, Direction::kForward, s).total_um,
                   Predict(m.axes[0].fallbacks[0], 300, Direction::kForward, s).total_um);
  // A model without fallbacks writes no "fallbacks" field (older readers see the same file).
  m.axes[0].fallbacks.clear();
  EXPECT_FALSE(ModelToJson(m)["axes"][0].contains("fallbacks"));
}

TEST(ModelJson, BadFallbacksAreRefusedByPath) {
  CompositeModel m;
  m.axes = {ExampleAxis()};
  m.axes[0].fallbacks = {ExampleFallback()};
  auto expect_error = [](const nlohmann::json& j, const std::string& field, const std::string& why) {
    try {
      ModelFromJson(j, "m.json");
      ADD_FAILURE() << "accepted: " << field;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("'" + field + "'"), std::string::npos) << what;
      EXPECT_NE(what.find(why), std::string::npos) << what;
    }
  };
  auto j = ModelToJson(m);
  j["axes"][0]["fallbacks"][0]["key_sensors"] = {"bearing", "nut"};  // every key of the axis: no fallback
  expect_error(j, "axes[0].fallbacks[0].key_sensors", "do without at least one");
  // Every key but no room term: a fallback for the ambient sensor, accepted.
  j["axes"][0]["fallbacks"][0].erase("ambient_sensor");
  j["axes"][0]["fallbacks"][0].erase("ambient_baseline_c");
  j["axes"][0]["fallbacks"][0]["key_temperature_rise"] = "from_baseline";
  EXPECT_EQ(ModelFromJson(j, "m.json").axes[0].fallbacks[0].ambient_sensor, "");
  j = ModelToJson(m);
  j["axes"][0]["fallbacks"][0]["axis"] = "Y";
  expect_error(j, "axes[0].fallbacks[0].axis", "not the axis 'X'");
  j = ModelToJson(m);
  j["axes"][0]["fallbacks"][0]["fallbacks"] = nlohmann::json::array({j["axes"][0]["fallbacks"][0]});
  expect_error(j, "axes[0].fallbacks[0].fallbacks", "no fallbacks of its own");
  j = ModelToJson(m);
  j["axes"][0]["fallbacks"] = "bearing";
  expect_error(j, "axes[0].fallbacks", "expected an array");
  j = ModelToJson(m);
  for (std::size_t k = 0; k < AxisModel::kMaxFallbacks; ++k) j["axes"][0]["fallbacks"].push_back(j["axes"][0]["fallbacks"][0]);
  expect_error(j, "axes[0].fallbacks", fmt::format("{} fallback models, at most {}", AxisModel::kMaxFallbacks + 1,
                                                   AxisModel::kMaxFallbacks));
  // The sensor it replaces: one of the axis's, and not one it uses itself; only a fallback has one.
  j = ModelToJson(m);
  j["axes"][0]["fallbacks"][0]["replaces"] = "nut";
  EXPECT_EQ(ModelFromJson(j, "m.json").axes[0].fallbacks[0].replaces, "nut");
  j["axes"][0]["fallbacks"][0]["replaces"] = "spindle";
  expect_error(j, "axes[0].fallbacks[0].replaces", "'spindle' is not a key sensor");
  j["axes"][0]["fallbacks"][0]["replaces"] = "bearing";
  expect_error(j, "axes[0].fallbacks[0].replaces", "'bearing' is a sensor this fallback itself uses");
  j["axes"][0]["fallbacks"][0]["replaces"] = "ambient";
  expect_error(j, "axes[0].fallbacks[0].replaces", "'ambient' is a sensor this fallback itself uses");
  j["axes"][0]["fallbacks"][0]["replaces"] = 3;
  expect_error(j, "axes[0].fallbacks[0].replaces", "");
  j = ModelToJson(m);
  j["axes"][0]["replaces"] = "nut";
  expect_error(j, "axes[0].replaces", "only a fallback model");
}

// A value no machine's model holds is refused with its JSON path, not turned by Predict into a ±inf
// or 1e308 correction that predict prints and export writes into a controller file.
TEST(ModelJson, ImplausibleValuesAreRefusedByPath) {
  CompositeModel m;
  m.axes = {ExampleAxis()};
  const auto refused = [](const nlohmann::json& j, const std::string& field, const std::string& why) {
    try {
      ModelFromJson(j, "m.json");
      ADD_FAILURE() << "accepted: " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.source(), "m.json");
      EXPECT_EQ(e.field(), field);
      EXPECT_NE(e.message().find(why), std::string::npos) << e.what();
    }
  };
  const auto good = ModelToJson(m);
  auto j = good;
  j["axes"][0]["reverse"]["geometric"]["error_um"][1] = 1e308;
  refused(j, "axes[0].reverse.geometric.error_um[1]", "beyond ±10000 µm");
  j = good;
  j["axes"][0]["reverse"]["geometric"]["position_mm"][2] = 1e6;
  refused(j, "axes[0].reverse.geometric.position_mm[2]", "beyond ±100000 mm");
  j = good;
  j["axes"][0]["forward"]["geometric"]["half_span_mm"] = 1e-300;
  refused(j, "axes[0].forward.geometric.half_span_mm", "at least 0.001 mm");
  j = good;
  j["axes"][0]["forward"]["geometric"]["coefficients_um"][2] = 1e6;  // Er(x) of a metre within the span
  refused(j, "axes[0].forward.geometric.coefficients_um", "beyond ±10000 µm");
  j = good;
  j["axes"][0]["rho_um_per_mm_per_c"] = 1e308;
  refused(j, "axes[0].rho_um_per_mm_per_c", "beyond ±1 µm/mm/°C");
  j = good;
  j["axes"][0]["forward"]["thermal"][1]["k_um_per_mm_per_c"][1] = -5.0;
  refused(j, "axes[0].forward.thermal[1].k_um_per_mm_per_c[1]", "beyond ±1 µm/mm/°C");
  j = good;
  j["axes"][0]["ambient_baseline_c"] = 1e308;
  refused(j, "axes[0].ambient_baseline_c", "outside the plausible");
  j = good;
  j["axes"][0]["baseline_temp_c"][1] = 293.15;
  refused(j, "axes[0].baseline_temp_c[1]", "looks like kelvin");
  j = good;
  j["axes"][0]["reference_position_mm"] = 1e6;
  refused(j, "axes[0].reference_position_mm", "beyond ±100000 mm");
  j = good;
  j["axes"][0]["key_lag_s"] = {1e308, 300.0};
  refused(j, "axes[0].key_lag_s[0]", "beyond ±1e+10 s");
  // The limits are wide: a negative ρ (Invar), a 20 m axis, a 5 mm error are read.
  j = good;
  j["axes"][0]["rho_um_per_mm_per_c"] = 0.002;
  j["axes"][0]["reference_position_mm"] = 20000;
  j["axes"][0]["reverse"]["geometric"]["error_um"][1] = -5000;
  EXPECT_NO_THROW(ModelFromJson(j, "m.json"));
}

// A model whose gains have no `off` entry predicted a dry machine with the flood gains, silently.
TEST(ModelJson, GainsWithoutAnOffEntryOrACoolantTwiceAreRefused) {
  CompositeModel m;
  m.axes = {ExampleAxis()};
  auto j = ModelToJson(m);
  j["axes"][0]["forward"]["thermal"].erase(0);  // only flood remains
  try {
    ModelFromJson(j, "m.json");
    ADD_FAILURE() << "a model without off gains was read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "axes[0].forward.thermal");
    EXPECT_NE(e.message().find("no \"off\" entry"), std::string::npos) << e.what();
  }
  j = ModelToJson(m);
  j["axes"][0]["forward"]["thermal"][1]["coolant"] = "off";
  try {
    ModelFromJson(j, "m.json");
    ADD_FAILURE() << "off gains given twice were read";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "axes[0].forward.thermal[1].coolant");
  }
  j = ModelToJson(m);
  j["axes"][0]["forward"]["thermal"] = nlohmann::json::array();  // no thermal part: geometric only
  EXPECT_NO_THROW(ModelFromJson(j, "m.json"));
}

}  // namespace
}  // namespace trueaxis::model
