// First-order thermal lag of the key sensors (model/thermal_lag.hpp): the filter's maths, the
// lag along a measurement's time series, the fit choosing τ by LOSO CV, τ = 0 leaving
// everything as before, and the model file's key_lag_s field.
#include "trueaxis/model/thermal_lag.hpp"

#include <cmath>
#include <filesystem>
#include <random>

#include <unistd.h>

#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::model {
namespace {

TEST(LagStep, ZeroTauIsTheRawReading) {
  EXPECT_EQ(LagStep(20.0, 25.0, 10.0, 0.0), 25.0);
  EXPECT_EQ(LagStep(20.0, 25.0, 10.0, -5.0), 25.0);
}

TEST(LagStep, OneTimeConstantCoversOneMinusOneOverE) {
  EXPECT_NEAR(LagStep(20.0, 26.0, 300.0, 300.0), 20.0 + 6.0 * (1.0 - std::exp(-1.0)), 1e-12);
  EXPECT_EQ(LagStep(20.0, 26.0, 0.0, 300.0), 20.0);  // no time passed: no change
}

TEST(LagStep, ExactForAHeldInputWhateverTheStep) {
  // Two steps of Δt/2 equal one step of Δt (the discretisation is the exact solution), so the
  // result does not depend on the cycle time.
  const double half = LagStep(LagStep(18.0, 24.0, 45.0, 200.0), 24.0, 45.0, 200.0);
  EXPECT_NEAR(half, LagStep(18.0, 24.0, 90.0, 200.0), 1e-12);
  double many = 18.0;
  for (int i = 0; i < 9000; ++i) many = LagStep(many, 24.0, 0.01, 200.0);
  EXPECT_NEAR(many, LagStep(18.0, 24.0, 90.0, 200.0), 1e-9);
}

TEST(LagStep, NoStateOrBackwardTimeRestartsAndNaNPropagates) {
  EXPECT_EQ(LagStep(std::nan(""), 22.0, 10.0, 100.0), 22.0);
  EXPECT_EQ(LagStep(20.0, 22.0, -1.0, 100.0), 22.0);
  EXPECT_TRUE(std::isnan(LagStep(20.0, std::nan(""), 10.0, 100.0)));
}

measure::Measurement Series(const std::vector<double>& times, const std::vector<double>& temps) {
  measure::Measurement m;
  m.sensor_names = {"nut"};
  for (std::size_t i = 0; i < times.size(); ++i) {
    measure::MeasurementPoint p;
    p.time_s = times[i];
    p.temperatures_c = {temps[i]};
    m.points.push_back(p);
  }
  return m;
}

TEST(LaggedSensorSeries, FollowsTimeOrderAndStartsAtTheFirstReading) {
  // Points listed out of time order: the filter runs in time order, results in file order.
  const auto m = Series({100, 0, 200}, {30, 20, 30});
  const auto s = LaggedSensorSeries(m, 0, 100);
  EXPECT_EQ(s[1], 20.0);
  const double at100 = 20 + 10 * (1 - std::exp(-1.0));
  EXPECT_NEAR(s[0], at100, 1e-12);
  EXPECT_NEAR(s[2], at100 + (30 - at100) * (1 - std::exp(-1.0)), 1e-12);
  const auto raw = LaggedSensorSeries(m, 0, 0);
  EXPECT_EQ(raw, (std::vector<double>{30, 20, 30}));
}

// A machine whose error follows the nut reading lagged by a known τ. Each state's nut
// temperature moves during the measurement (warm-up ramps, a cool-down, a step), so a static
// model of the raw reading cannot follow it.
struct LaggedMachine {
  double tau_true_s = 600;
  double k = -0.008;  // µm per mm per °C
  double noise_um = 0.1;
  double dt_s = 12;
  std::vector<FitState> MakeStates(unsigned seed) const {
    const std::vector<testing::TimedProfile> profiles = {
        {"cold", "off", 20, 0, 0},          {"warm-1", "off", 20.5, 0.004, 0},   {"warm-2", "off", 22, 0.002, 1.5},
        {"cooldown-1", "off", 27, -0.003, -2.0}, {"warm-3", "off", 24, 0.0015, 3.0}, {"cooldown-2", "off", 25, -0.001, -3.0}};
    double lagged = std::nan("");
    return testing::MakeTimedStates(profiles, dt_s, noise_um, seed,
                                    [&](const testing::TimedProfile&, double nut, double x, bool first) {
                                      lagged = first ? nut : LagStep(lagged, nut, dt_s, tau_true_s);
                                      return k * (lagged - 20.0) * (0.0 - x);
                                    });
  }
};

FitOptions LagFitOptions() { return testing::TimedFitOptions(); }

TEST(LagFit, RecoversAKnownTimeConstantAndItsGain) {
  LaggedMachine mach;
  const auto states = mach.MakeStates(11);
  const auto r = FitCompositeModel(states, LagFitOptions());
  const auto& a = r.model.axes.at(0);
  ASSERT_EQ(a.key_lag_s.size(), 1u);
  EXPECT_EQ(a.key_lag_s[0], 600);
  EXPECT_EQ(r.summary.axes[0].key_lag_s, 600);
  EXPECT_NEAR(a.directions[0].thermal[0].k_um_per_mm_per_c[0], mach.k, 0.05 * std::fabs(mach.k));
  // The CV at τ = 600 s is at the noise, the static model's is far above it.
  const auto& cands = r.summary.axes[0].lag_candidates;
  ASSERT_EQ(cands.size(), 6u);
  EXPECT_LT(cands[3][1], 2 * mach.noise_um);
  EXPECT_GT(cands[0][1], 3 * cands[3][1]);
  // Held-out day (another seed): predicting along its time series leaves only the noise.
  const auto held = mach.MakeStates(12);
  const auto res = PredictionResidual(a, held[2].measurement, CoolantState::kOff);
  double ss = 0;
  for (const auto& p : res.points) ss += p.deviation_um * p.deviation_um;
  EXPECT_LT(std::sqrt(ss / res.points.size()), 2.5 * mach.noise_um);
}

TEST(LagFit, NoLagInTheDataKeepsTheStaticModelUnchanged) {
  // Temperatures constant within each state (the synthetic machine of model_fit_test):
  // lagging cannot help, so the default grid must give exactly the static fit.
  testing::SyntheticMachine sm;
  const auto states = sm.MakeStates(sm.DefaultStates());
  FitOptions with_grid;  // default grid
  FitOptions no_lag;
  no_lag.key_lag_grid_s = {0};
  const auto a = FitCompositeModel(states, with_grid);
  const auto b = FitCompositeModel(states, no_lag);
  ASSERT_EQ(a.model.axes.size(), 1u);
  EXPECT_TRUE(a.model.axes[0].key_lag_s.empty());
  EXPECT_EQ(a.model.axes[0].key_sensors, b.model.axes[0].key_sensors);
  for (int d = 0; d < 2; ++d)
    EXPECT_EQ(a.model.axes[0].directions[d].thermal[0].k_um_per_mm_per_c,
              b.model.axes[0].directions[d].thermal[0].k_um_per_mm_per_c);
  EXPECT_FALSE(ModelToJson(a.model)["axes"][0].contains("key_lag_s"));
  EXPECT_FALSE(a.summary.axes[0].lag_reason.empty());
}

TEST(LagFit, ZeroTauPredictsExactlyTheRawReadings) {
  LaggedMachine mach;
  const auto states = mach.MakeStates(3);
  auto o = LagFitOptions();
  o.key_lag_grid_s = {0};
  auto axis = FitCompositeModel(states, o).model.axes.at(0);
  const auto& m = states[3].measurement;
  const auto before = PredictedMeasurement(axis, m, CoolantState::kOff);
  axis.key_lag_s = {0.0};  // explicit zero: same as absent
  const auto after = PredictedMeasurement(axis, m, CoolantState::kOff);
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const auto t = TemperaturesForPoint(axis, m, m.points[i]);
    const double raw = Predict(axis, m.points[i].target_mm, m.points[i].direction, {t.key_temp_c, t.ambient_c}).total_um;
    EXPECT_EQ(before.points[i].deviation_um, raw);
    EXPECT_EQ(after.points[i].deviation_um, raw);
  }
}

TEST(LagModelFile, RoundTripsAndRejectsBadValues) {
  LaggedMachine mach;
  const auto r = FitCompositeModel(mach.MakeStates(5), LagFitOptions());
  auto j = ModelToJson(r.model);
  ASSERT_TRUE(j["axes"][0].contains("key_lag_s"));
  const auto back = ModelFromJson(j, "m.json");
  EXPECT_EQ(back.axes[0].key_lag_s, r.model.axes[0].key_lag_s);
  auto bad = j;
  bad["axes"][0]["key_lag_s"] = {-5.0};
  try {
    ModelFromJson(bad, "m.json");
    FAIL() << "negative τ accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("axes[0].key_lag_s[0]"), std::string::npos) << e.what();
  }
  bad["axes"][0]["key_lag_s"] = {600.0, 600.0};  // two values for one key sensor
  EXPECT_THROW(ModelFromJson(bad, "m.json"), InputError);
  auto absent = j;
  absent["axes"][0].erase("key_lag_s");
  EXPECT_TRUE(ModelFromJson(absent, "m.json").axes[0].key_lag_s.empty());
}

TEST(LagFitOptions, NegativeGridValueIsInvalid) {
  FitOptions o;
  o.key_lag_grid_s = {0, -10};
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("key_lag_grid_s"), std::string::npos);
}

}  // namespace
}  // namespace trueaxis::model

namespace trueaxis::model {
namespace {

// A manifest naming the campaign's temperature_log gives each file its history, and the lag
// runs through it before the file's points.
TEST(LagHistory, ManifestTemperatureLogFeedsTheFilterBeforeTheFile) {
  namespace fs = std::filesystem;
  const fs::path dir = testing::OneFileCampaignDir("lag_history", "30");
  // Nut at 20 °C for hours, then 30 °C from 100 s before the file (campaign clock: file at 10000 s).
  std::string log = "time_s,date,coolant,t_nut_c,t_other_c\n";
  for (int t = 0; t < 10000; t += 50) log += std::to_string(t) + ",d,off," + (t < 9900 ? "20" : "30") + ",1\n";
  log += "10050,d,off,30,1\n";  // after the start: not history
  WriteTextFile((dir / "temperature_log.csv").string(), log);
  const auto states = LoadFitStates({}, (dir / "manifest.json").string());
  ASSERT_EQ(states.size(), 1u);
  const auto& h = states[0].history;
  ASSERT_FALSE(h.empty());
  EXPECT_LT(h.time_s.back(), 0);
  EXPECT_GE(h.time_s.front(), -TemperatureHistory::kWindowS);
  EXPECT_EQ(h.temps_c.back().size(), 1u);  // mapped onto the file's sensors (nut only)
  const auto& m = states[0].measurement;
  // Without history the filter starts at the file's 30 °C; with it, at ~20 °C + 100 s of 30 °C.
  EXPECT_EQ(LaggedSensorSeries(m, 0, 100)[0], 30.0);
  const auto lagged = LaggedSensorSeries(m, 0, 100, &h);
  // Each reading is held over the interval since the previous one: the first 30 °C row (−100 s)
  // counts from the 20 °C row before it (−150 s), so 150 s of 30 °C at τ = 100 s.
  EXPECT_NEAR(lagged[0], 20 + 10 * (1 - std::exp(-1.5)), 1e-9);
  EXPECT_GT(lagged[1], lagged[0]);
  EXPECT_LT(lagged[1], 30.0);

  // A bad number in the log names its line and column.
  WriteTextFile((dir / "temperature_log.csv").string(), "time_s,t_nut_c\n0,20\n50,abc\n");
  try {
    LoadFitStates({}, (dir / "manifest.json").string());
    FAIL() << "bad log accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(":3:"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("t_nut_c"), std::string::npos) << e.what();
  }
  fs::remove(dir / "temperature_log.csv");
  EXPECT_THROW(LoadFitStates({}, (dir / "manifest.json").string()), InputError);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::model
