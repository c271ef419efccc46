// A falling key's longer lag (AxisModel::key_lag_fall_factor, FitOptions::key_lag_fall_grid; issue
// 10): the screw keeps its heat after the nut's friction stops, so while the key reading falls its
// effective temperature follows it more slowly than while it rises.
#include <cmath>
#include <limits>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/thermal_lag.hpp"
#include "trueaxis/model/thermal_state.hpp"

namespace trueaxis::model {
namespace {

using ::testing::HasSubstr;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

AxisModel LaggedAxis(double fall_factor) {
  AxisModel a = testing::OneKeyAxis(-0.01);
  a.key_lag_s = {300};
  a.key_lag_fall_factor = fall_factor;
  a.key_loss_s[static_cast<std::size_t>(CoolantState::kFlood)] = {600};
  return a;
}

TEST(LagFall, TheStateFollowsAFallingReadingWithTheLongerTau) {
  const AxisModel a = LaggedAxis(4);
  AxisThermalState st;
  std::vector<double> reading{30};
  AdvanceThermalState(a, st, {reading, kNaN, CoolantState::kOff}, 0);  // starts at the reading
  ASSERT_TRUE(st.valid);
  reading[0] = 20;  // the nut cools: τ = 4 × 300 s
  AdvanceThermalState(a, st, {reading, kNaN, CoolantState::kOff}, 600);
  const double fallen = 20 + 10 * std::exp(-600.0 / 1200.0);
  EXPECT_NEAR(st.key_c[0], fallen, 1e-9);
  reading[0] = 30;  // heats again: τ = 300 s
  AdvanceThermalState(a, st, {reading, kNaN, CoolantState::kOff}, 60);
  EXPECT_NEAR(st.key_c[0], 30 + (fallen - 30) * std::exp(-60.0 / 300.0), 1e-9);
  // Under the flood coolant (a loss τ) the coolant's observer governs, with the plain τ.
  AxisThermalState flood;
  reading[0] = 30;
  AdvanceThermalState(a, flood, {reading, kNaN, CoolantState::kFlood}, 0);
  reading[0] = 24;
  AdvanceThermalState(a, flood, {reading, kNaN, CoolantState::kFlood}, 120);
  EXPECT_NEAR(flood.key_c[0], ObserverStep(30, 24, 20, 120, 300, 600), 1e-12);
  // Factor 1 is the symmetric lag, exactly as before.
  const AxisModel one = LaggedAxis(1);
  AxisThermalState sym;
  reading[0] = 30;
  AdvanceThermalState(one, sym, {reading, kNaN, CoolantState::kOff}, 0);
  reading[0] = 20;
  AdvanceThermalState(one, sym, {reading, kNaN, CoolantState::kOff}, 600);
  EXPECT_EQ(sym.key_c[0], LagStep(30, 20, 600, 300));
}

// A synthetic axis whose screw follows the nut with τ 600 s while it rises and 2400 s while it
// falls (factor 4); warm-ups, steps and cool-downs, coolant off.
std::vector<FitState> AsymmetricStates(unsigned seed, double fall_tau_s) {
  const double k = -0.008, dt_s = 12;
  const std::vector<testing::TimedProfile> profiles = {
      {"cold", "off", 20, 0, 0},           {"warm-1", "off", 20.5, 0.004, 0},    {"warm-2", "off", 22, 0.002, 1.5},
      {"cooldown-1", "off", 27, -0.003, -2}, {"warm-3", "off", 24, 0.0015, 3},   {"cooldown-2", "off", 28, -0.002, -3},
      {"cooldown-3", "off", 26, -0.004, 0}};
  double screw = kNaN;
  return testing::MakeTimedStates(profiles, dt_s, 0.1, seed, [&](const testing::TimedProfile&, double nut, double x, bool first) {
    screw = first ? nut : LagStep(screw, nut, dt_s, nut < screw ? fall_tau_s : 600.0);
    return k * (screw - 20.0) * (0.0 - x);
  });
}

using testing::ResidualRms;

TEST(LagFall, TheFitRecoversAKnownFallFactorAndKeepsNoneWhenThereIsNone) {
  const auto o = testing::TimedFitOptions();
  ASSERT_EQ(o.key_lag_fall_grid, (std::vector<double>{1, 2, 4, 8}));
  const auto r = FitCompositeModel(AsymmetricStates(31, 2400), o);
  const auto& a = r.model.axes.at(0);
  ASSERT_EQ(a.key_lag_s, (std::vector<double>{600.0}));
  EXPECT_EQ(a.key_lag_fall_factor, 4.0);
  EXPECT_THAT(r.summary.axes.at(0).lag_reason, HasSubstr("with a falling key lagging 4× longer"));
  // Held out (another seed): the cool-downs are followed to the noise.
  const auto held = AsymmetricStates(32, 2400);
  for (const auto& s : held) EXPECT_LT(ResidualRms(a, s), 2.5 * 0.1) << s.label;
  // One τ both ways (the lag before): the cool-downs are not.
  auto sym_options = o;
  sym_options.key_lag_fall_grid = {1};
  const auto sym = FitCompositeModel(AsymmetricStates(31, 2400), sym_options).model.axes.at(0);
  EXPECT_EQ(sym.key_lag_fall_factor, 1.0);
  double worst = 0;
  for (const auto& s : held) worst = std::max(worst, ResidualRms(sym, s));
  EXPECT_GT(worst, 4 * 0.1);
  // A symmetric truth: the fit keeps one τ.
  const auto plain = FitCompositeModel(AsymmetricStates(33, 600), o).model.axes.at(0);
  EXPECT_EQ(plain.key_lag_s, (std::vector<double>{600.0}));
  EXPECT_EQ(plain.key_lag_fall_factor, 1.0);
}

TEST(LagFall, ModelFileAndOptions) {
  CompositeModel m;
  m.axes.push_back(LaggedAxis(4));
  const auto j = ModelToJson(m);
  ASSERT_TRUE(j["axes"][0].contains("key_lag_fall_factor"));
  EXPECT_EQ(ModelFromJson(j, "m.json").axes[0].key_lag_fall_factor, 4.0);
  auto older = j;
  older["axes"][0].erase("key_lag_fall_factor");
  EXPECT_EQ(ModelFromJson(older, "m.json").axes[0].key_lag_fall_factor, 1.0);
  CompositeModel sym;
  sym.axes.push_back(LaggedAxis(1));
  EXPECT_FALSE(ModelToJson(sym)["axes"][0].contains("key_lag_fall_factor"));  // the file as before
  for (const nlohmann::json& bad : {nlohmann::json(0.5), nlohmann::json("slow"), nlohmann::json(-2.0)}) {
    auto b = j;
    b["axes"][0]["key_lag_fall_factor"] = bad;
    try {
      ModelFromJson(b, "m.json");
      ADD_FAILURE() << "accepted " << bad.dump();
    } catch (const InputError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr("key_lag_fall_factor")) << bad.dump();
    }
  }
  FitOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.key_lag_fall_grid = {1, 0.5};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THAT(why, HasSubstr("key_lag_fall_grid"));
}

}  // namespace
}  // namespace trueaxis::model
