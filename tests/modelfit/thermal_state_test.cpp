// The model's thermal state (model/thermal_state.hpp, issue 10): the observer step's maths, the
// state the compensator advances, the fit recovering a known coolant memory (lag + loss τ) on a
// synthetic axis whose screw temperature is known, the gains' fitted envelope, and the model file.
#include "trueaxis/model/thermal_state.hpp"

#include <cmath>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/thermal_lag.hpp"

namespace trueaxis::model {
namespace {

TEST(ObserverStep, WithoutLossItIsTheLag) {
  EXPECT_EQ(ObserverStep(20.0, 26.0, 20.0, 30.0, 300.0, 0.0), LagStep(20.0, 26.0, 30.0, 300.0));
  EXPECT_EQ(ObserverStep(20.0, 26.0, 20.0, 30.0, 0.0, 600.0), 26.0);  // no lag: the reading itself
}

TEST(ObserverStep, ExactForHeldInputsAndSettlesBetweenReadingAndSink) {
  const double one = ObserverStep(22.0, 30.0, 20.0, 90.0, 300.0, 600.0);
  const double two = ObserverStep(ObserverStep(22.0, 30.0, 20.0, 45.0, 300.0, 600.0), 30.0, 20.0, 45.0, 300.0, 600.0);
  EXPECT_NEAR(one, two, 1e-12);
  double many = 22.0;
  for (int i = 0; i < 9000; ++i) many = ObserverStep(many, 30.0, 20.0, 0.01, 300.0, 600.0);
  EXPECT_NEAR(many, one, 1e-9);
  // Steady state: (raw/τ_lag + sink/τ_loss) / (1/τ_lag + 1/τ_loss) = 20 + 10·(1/300)/(1/300 + 1/600).
  EXPECT_NEAR(ObserverStep(22.0, 30.0, 20.0, 1e6, 300.0, 600.0), 20.0 + 10.0 * 2.0 / 3.0, 1e-9);
}

TEST(AxisThermalState, RestartsAtTheReadingsAndUsesTheCoolantsLoss) {
  AxisModel a;
  a.key_sensors = {"nut"};
  a.baseline_temp_c = {20.0};
  a.key_lag_s = {300.0};
  a.key_loss_s[static_cast<std::size_t>(CoolantState::kFlood)] = {600.0};
  AxisThermalState s;
  const double hot[] = {30.0};
  AdvanceThermalState(a, s, {hot, std::nan(""), CoolantState::kOff}, 10.0);
  EXPECT_TRUE(s.valid);
  EXPECT_EQ(s.key_c[0], 30.0);  // not valid before: restarted at the reading
  const double cool[] = {25.0};
  AdvanceThermalState(a, s, {cool, std::nan(""), CoolantState::kOff}, 60.0);
  EXPECT_NEAR(s.key_c[0], LagStep(30.0, 25.0, 60.0, 300.0), 1e-12);
  const double before = s.key_c[0];
  AdvanceThermalState(a, s, {cool, std::nan(""), CoolantState::kFlood}, 60.0);
  EXPECT_NEAR(s.key_c[0], ObserverStep(before, 25.0, 20.0, 60.0, 300.0, 600.0), 1e-12);
  // Above-ambient models draw to the baseline moved with the room.
  a.key_rise_above_ambient = true;
  a.ambient_sensor = "air";
  a.ambient_baseline_c = 19.0;
  EXPECT_NEAR(KeySinkC(a, 0, 21.5), 22.5, 1e-12);
  // A lost key: the state is invalid and the next good reading restarts it.
  const double lost[] = {std::nan("")};
  AdvanceThermalState(a, s, {lost, 21.0, CoolantState::kOff}, 1.0);
  EXPECT_FALSE(s.valid);
  AdvanceThermalState(a, s, {hot, 21.0, CoolantState::kOff}, 1.0);
  EXPECT_EQ(s.key_c[0], 30.0);
}

TEST(AxisThermalState, HasThermalDynamicsOnlyWithAPositiveLagOrLoss) {
  AxisModel a;
  a.key_sensors = {"nut", "bearing"};
  EXPECT_FALSE(HasThermalDynamics(a));
  a.key_lag_s = {0.0, std::nan("")};
  a.key_loss_s[static_cast<std::size_t>(CoolantState::kMist)] = {0.0, -5.0};
  EXPECT_FALSE(HasThermalDynamics(a));  // zero, negative and NaN time constants are "none"
  a.key_lag_s = {0.0, 120.0};
  EXPECT_TRUE(HasThermalDynamics(a));
  a.key_lag_s.clear();
  a.key_loss_s[static_cast<std::size_t>(CoolantState::kFlood)] = {0.0, 900.0};
  EXPECT_TRUE(HasThermalDynamics(a));  // a loss under one coolant only is enough
}

// An axis whose thermal error follows a screw temperature known by construction: the nut reading
// through a lag of τ_lag and, while the flood coolant runs, drawn to the room (20 °C) with τ_loss —
// exactly the observer's structure, so the fit must find both time constants and one gain.
struct CoolantMemoryAxis {
  double tau_lag_s = 600, tau_loss_s = 1200;
  double k = -0.008;  // µm per mm per °C of screw rise
  double noise_um = 0.1;
  double dt_s = 12;
  std::vector<FitState> MakeStates(unsigned seed) const {
    const std::vector<testing::TimedProfile> profiles = {
        {"cold", "off", 20, 0, 0},           {"warm-1", "off", 20.5, 0.004, 0},  {"warm-2", "off", 22, 0.002, 1.5},
        {"cooldown-1", "off", 27, -0.003, -2}, {"warm-3", "off", 24, 0.0015, 3},  {"coolant-1", "flood", 24, 0.002, 0},
        {"coolant-2", "flood", 26, -0.002, 2}, {"coolant-3", "flood", 23, 0.003, -1.5}};
    double screw = std::nan("");
    return testing::MakeTimedStates(profiles, dt_s, noise_um, seed,
                                    [&](const testing::TimedProfile& pr, double nut, double x, bool first) {
                                      const double loss = pr.coolant == "flood" ? tau_loss_s : 0.0;
                                      screw = first ? nut : ObserverStep(screw, nut, 20.0, dt_s, tau_lag_s, loss);
                                      return k * (screw - 20.0) * (0.0 - x);
                                    });
  }
};

FitOptions MemoryFitOptions() {
  FitOptions o = testing::TimedFitOptions();
  o.coolant_loss_grid_s = {0, 300, 600, 1200, 2400, 4800};
  return o;
}

using testing::ResidualRms;

TEST(CoolantMemoryFit, RecoversTheKnownLagLossAndGain) {
  CoolantMemoryAxis axis;
  const auto r = FitCompositeModel(axis.MakeStates(21), MemoryFitOptions());
  const auto& a = r.model.axes.at(0);
  ASSERT_EQ(a.key_lag_s, (std::vector<double>{600.0}));
  EXPECT_EQ(a.KeyLossS(0, CoolantState::kFlood), 1200.0);
  EXPECT_EQ(a.KeyLossS(0, CoolantState::kOff), 0.0);
  // One set of gains for every state: no flood entry, the off gain is the true k.
  for (int d = 0; d < 2; ++d) {
    ASSERT_EQ(a.directions[d].thermal.size(), 1u);
    EXPECT_NEAR(a.directions[d].thermal[0].k_um_per_mm_per_c[0], axis.k, 0.05 * std::fabs(axis.k));
  }
  // A held-out day (another seed), coolant states included: only the noise remains.
  const auto held = axis.MakeStates(22);
  for (const auto& s : held) EXPECT_LT(ResidualRms(a, s), 2.5 * axis.noise_um) << s.label;
  // Without the memory (gains per coolant state: the fit's default, which says it did not try the
  // memory) the flood states are not followed.
  const auto table_fit = FitCompositeModel(axis.MakeStates(21), testing::TimedFitOptions());
  EXPECT_THAT(table_fit.summary.axes.at(0).coolant_notes, ::testing::Contains(::testing::HasSubstr("memory was not tried")));
  const auto& table = table_fit.model.axes.at(0);
  EXPECT_EQ(table.directions[0].thermal.size(), 2u);
  double worst = 0;
  for (const auto& s : held)
    if (s.coolant == CoolantState::kFlood) worst = std::max(worst, ResidualRms(table, s));
  EXPECT_GT(worst, 4 * axis.noise_um);
}

TEST(CoolantMemoryModelFile, RoundTripsAndRejectsBadValues) {
  CoolantMemoryAxis axis;
  const auto r = FitCompositeModel(axis.MakeStates(5), MemoryFitOptions());
  auto j = ModelToJson(r.model);
  ASSERT_TRUE(j["axes"][0].contains("key_loss_s"));
  ASSERT_TRUE(j["axes"][0]["forward"]["thermal"][0].contains("key_rise_range_c"));
  const auto back = ModelFromJson(j, "m.json");
  EXPECT_EQ(back.axes[0].key_loss_s, r.model.axes[0].key_loss_s);
  const auto& g0 = r.model.axes[0].directions[0].thermal[0];
  const auto& g1 = back.axes[0].directions[0].thermal[0];
  EXPECT_EQ(g1.key_rise_range_c, g0.key_rise_range_c);
  EXPECT_DOUBLE_EQ(g1.min_tan_beta_um_per_mm, g0.min_tan_beta_um_per_mm);
  EXPECT_DOUBLE_EQ(g1.max_tan_beta_um_per_mm, g0.max_tan_beta_um_per_mm);
  auto bad = j;
  bad["axes"][0]["key_loss_s"] = {{"flood", {-1.0}}};
  EXPECT_THROW(ModelFromJson(bad, "m.json"), InputError);
  bad["axes"][0]["key_loss_s"] = {{"steam", {600.0}}};
  try {
    ModelFromJson(bad, "m.json");
    FAIL() << "unknown coolant accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key_loss_s"), std::string::npos) << e.what();
  }
  bad = j;
  bad["axes"][0]["forward"]["thermal"][0]["key_rise_range_c"] = {{5.0, 1.0}};
  EXPECT_THROW(ModelFromJson(bad, "m.json"), InputError);
  auto absent = j;
  absent["axes"][0].erase("key_loss_s");
  absent["axes"][0]["forward"]["thermal"][0].erase("key_rise_range_c");
  absent["axes"][0]["forward"]["thermal"][0].erase("tan_beta_range_um_per_mm");
  const auto plain = ModelFromJson(absent, "m.json");
  EXPECT_EQ(plain.axes[0].KeyLossS(0, CoolantState::kFlood), 0.0);
  EXPECT_FALSE(plain.axes[0].directions[0].thermal[0].HasTanBetaRange());
}

TEST(FittedEnvelope, PredictHoldsTheRiseAndSlopeBeyondItAndFlagsIt) {
  AxisModel a;
  a.reference_position_mm = 0;
  a.key_sensors = {"nut", "bearing"};
  a.baseline_temp_c = {20.0, 20.0};
  ThermalGains g;
  g.k_um_per_mm_per_c = {-0.05, 0.035};  // large gains of opposite sign, as from a few states
  g.key_rise_range_c = {{-1.0, 5.0}, {-1.0, 6.0}};
  g.min_tan_beta_um_per_mm = -0.12;
  g.max_tan_beta_um_per_mm = 0.12;
  for (auto& d : a.directions) d.thermal = {g};
  const double inside[] = {24.0, 23.0};
  const auto p = Predict(a, 500, Direction::kForward, {inside, std::nan(""), CoolantState::kOff, true});
  EXPECT_FALSE(p.tan_beta_limited);
  EXPECT_NEAR(p.tan_beta_um_per_mm, -0.05 * 4 + 0.035 * 3, 1e-12);
  // The bearing hotter than any fitted state: held at its 6 °C, and flagged.
  const double hot_bearing[] = {24.0, 30.0};
  const auto q = Predict(a, 500, Direction::kForward, {hot_bearing, std::nan(""), CoolantState::kOff, true});
  EXPECT_TRUE(q.tan_beta_limited);
  EXPECT_NEAR(q.tan_beta_um_per_mm, -0.05 * 4 + 0.035 * 6, 1e-12);
  // Rises inside their ranges, but a mix that gives a slope beyond the fitted one: tanβ held.
  const double mix[] = {25.0, 20.0};
  const auto m = Predict(a, 500, Direction::kForward, {mix, std::nan(""), CoolantState::kOff, true});
  EXPECT_TRUE(m.tan_beta_limited);
  EXPECT_DOUBLE_EQ(m.tan_beta_um_per_mm, -0.12);  // −0.05·5 + 0.035·0 = −0.25 asked
  EXPECT_DOUBLE_EQ(m.thermal_um, -0.12 * (0 - 500));
}

TEST(FittedEnvelope, TheFitRecordsTheRangeOfItsStates) {
  CoolantMemoryAxis axis;
  const auto states = axis.MakeStates(9);
  const auto r = FitCompositeModel(states, MemoryFitOptions());
  const auto& a = r.model.axes.at(0);
  const auto& g = a.directions[0].thermal.at(0);
  ASSERT_EQ(g.key_rise_range_c.size(), 1u);
  // Every fitted point's (observed) rise lies inside, with the margin beyond the extremes.
  for (const auto& s : states) {
    const auto temps = LaggedKeyTemperatures(a, s.measurement, nullptr, s.coolant);
    for (const auto& t : temps) {
      const double rise = t.key_temp_c[0] - a.baseline_temp_c[0];
      EXPECT_GE(rise, g.key_rise_range_c[0][0]);
      EXPECT_LE(rise, g.key_rise_range_c[0][1]);
    }
  }
  // No envelope when asked for none: the model extrapolates as before.
  auto o = MemoryFitOptions();
  o.tan_beta_margin = -1;
  const auto free = FitCompositeModel(states, o).model.axes.at(0);
  EXPECT_TRUE(free.directions[0].thermal[0].key_rise_range_c.empty());
  EXPECT_FALSE(free.directions[0].thermal[0].HasTanBetaRange());
}

}  // namespace
}  // namespace trueaxis::model

namespace trueaxis::model {
namespace {

TEST(CoolantMemoryOptions, BadValuesAreInvalid) {
  std::string why;
  FitOptions o;
  EXPECT_TRUE(o.IsValid(&why)) << why;
  o.coolant_loss_grid_s = {0, -600};
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("coolant_loss_grid_s"), std::string::npos);
  o = FitOptions{};
  o.coolant_memory_off_tolerance = -0.5;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("coolant_memory_off_tolerance"), std::string::npos);
  o = FitOptions{};
  o.tan_beta_margin = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
}

}  // namespace
}  // namespace trueaxis::model
