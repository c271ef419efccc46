// The motion-heat input (AxisModel::motion_lag_s, model/motion_heat.hpp; issue 10): the axis's feed
// in m/min through a first-order lag, as one more key of tanβ — the runtime's per-cycle step, the
// fit's series along a logged travel history, the fit that finds it, and the model file.
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "support/cli_runner.hpp"
#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/model/compensation_bound.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/modelfit/motion_heat.hpp"
#include "trueaxis/model/thermal_state.hpp"

namespace trueaxis::model {
namespace {

using ::testing::HasSubstr;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(MotionHeatStep, FollowsTheFeedWithItsTimeConstantAndDecaysAtRest) {
  AxisThermalState st;
  AdvanceMotionHeat(600, st, 0, 0.01);  // the first position only starts the difference
  EXPECT_EQ(st.motion_m_per_min, 0);
  // 5 m/min (83.33 mm/s) for 600 s in 10 ms cycles: 1 − 1/e of the feed.
  double x = 0;
  for (int i = 0; i < 60000; ++i) AdvanceMotionHeat(600, st, x += 0.8333333333333334, 0.01);
  EXPECT_NEAR(st.motion_m_per_min, 5 * (1 - std::exp(-1.0)), 1e-6);
  const double at_stop = st.motion_m_per_min;
  // Back and forth counts the path, not the displacement.
  AxisThermalState zigzag;
  for (int i = 0; i <= 60000; ++i) AdvanceMotionHeat(600, zigzag, (i % 2) ? 0.8333333333333334 : 0.0, 0.01);
  EXPECT_NEAR(zigzag.motion_m_per_min, at_stop, 1e-6);
  // At rest for τ: down by e.
  AdvanceMotionHeat(600, st, x, 600);
  EXPECT_NEAR(st.motion_m_per_min, at_stop * std::exp(-1.0), 1e-12);
  // An unknown position (the link down) counts as standstill, and the next one starts afresh
  // instead of taking the whole jump as one step's feed.
  AdvanceMotionHeat(600, st, kNaN, 60);
  EXPECT_NEAR(st.motion_m_per_min, at_stop * std::exp(-1.0) * std::exp(-0.1), 1e-12);
  const double before = st.motion_m_per_min;
  AdvanceMotionHeat(600, st, x + 500, 0.01);
  EXPECT_NEAR(st.motion_m_per_min, before * std::exp(-0.01 / 600), 1e-12);
}

// A model with a motion input advances it in AdvanceThermalState and keeps it through a key's
// restart (a lost sensor does not change the axis's motion history).
TEST(MotionHeatStep, AdvanceThermalStateCarriesItThroughAKeyRestart) {
  AxisModel a = testing::OneKeyAxis(-0.01);
  a.motion_lag_s = 1200;
  EXPECT_TRUE(HasThermalDynamics(a));
  AxisThermalState st;
  std::vector<double> reading{25};
  double x = 0;
  for (int i = 0; i < 1000; ++i) AdvanceThermalState(a, st, {reading, kNaN, CoolantState::kOff, x += 10}, 1.0);
  const double m = st.motion_m_per_min;
  EXPECT_NEAR(m, 0.6 * (1 - std::exp(-999.0 / 1200)), 1e-9);  // 10 mm/s = 0.6 m/min
  reading[0] = kNaN;  // the key is lost: its state restarts, M goes on
  AdvanceThermalState(a, st, {reading, kNaN, CoolantState::kOff, x += 10}, 1.0);
  EXPECT_FALSE(st.valid);
  EXPECT_NEAR(st.motion_m_per_min, 0.6 + (m - 0.6) * std::exp(-1.0 / 1200), 1e-12);
}

// The series the fit computes from a log (30 s rows of the travelled path) is the runtime's
// per-cycle M for the same motion, at any point between rows.
TEST(MotionHeatSeries, MatchesThePerCycleStepAlongALoggedTravel) {
  const double tau = 900;
  // Motion: rest, 3 m/min for 40 min, rest 20 min, 1.2 m/min for 30 min (from −2 h before the start).
  auto feed_at = [](double t) {  // mm/s at time t (s, relative to the start)
    if (t < -7200 + 600) return 0.0;
    if (t < -7200 + 600 + 2400) return 50.0;
    if (t < -7200 + 600 + 2400 + 1200) return 0.0;
    if (t < -7200 + 600 + 2400 + 1200 + 1800) return 20.0;
    return 0.0;
  };
  TemperatureHistory h;
  double travel = 0;
  for (double t = -7200; t <= 3000; t += 30) {
    h.travel_time_s.push_back(t);
    h.travel_mm.push_back(travel);
    for (int k = 0; k < 3000; ++k) travel += feed_at(t + k * 0.01) * 0.01;
  }
  measure::Measurement m;
  for (double t : {0.0, 17.0, 1000.0, 2999.0}) {
    measure::MeasurementPoint p;
    p.time_s = t;
    m.points.push_back(p);
  }
  const auto series = MotionHeatAtPoints(m, h, tau);
  AxisThermalState st;
  double x = 0, t = -7200;
  AdvanceMotionHeat(tau, st, x, 0);
  std::size_t next = 0;
  while (next < m.points.size()) {
    if (t >= *m.points[next].time_s - 1e-9) {
      EXPECT_NEAR(series[next], st.motion_m_per_min, 1e-3) << "point at " << *m.points[next].time_s << " s";
      ++next;
      continue;
    }
    x += feed_at(t) * 0.01;
    t += 0.01;
    AdvanceMotionHeat(tau, st, x, 0.01);
  }
  EXPECT_GT(series[0], 0.25);  // the last motion (20 min before) is still felt at the start
  // No travel in the history, or no lag: not known.
  EXPECT_TRUE(std::isnan(MotionHeatAtPoints(m, TemperatureHistory{}, tau)[0]));
  EXPECT_TRUE(std::isnan(MotionHeatAtPoints(m, h, 0)[0]));
}

// The manifest's machine log gives each file its axis's travel, from the window before the start to
// past the file's end; a bad or shrinking travel is refused with its line and column.
TEST(MotionHeatHistory, TheLogsTravelColumnReachesPastTheFileAndBadValuesAreNamed) {
  namespace fs = std::filesystem;
  const fs::path dir = testing::OneFileCampaignDir("motion_history", "25");
  // X runs at 1 m/min (1000 mm per minute) from 3000 s on; Y never moves. File at 10000 s.
  std::string log = "time_s,date,coolant,x_mm,y_mm,x_travel_mm,y_travel_mm,t_nut_c\n";
  for (int t = 0; t <= 10200; t += 60)
    log += fmt::format("{},d,off,0,0,{},0,25\n", t, t < 3000 ? 0 : (t - 3000) * 1000 / 60);
  WriteTextFile((dir / "temperature_log.csv").string(), log);
  const auto states = LoadFitStates({}, (dir / "manifest.json").string());
  ASSERT_EQ(states.size(), 1u);
  const auto& h = states[0].history;
  ASSERT_TRUE(h.HasTravel());
  EXPECT_GE(h.travel_time_s.front(), -TemperatureHistory::kWindowS);
  EXPECT_GT(h.travel_time_s.back(), 100);  // one row past the file's last point
  const auto m = MotionHeatAtPoints(states[0].measurement, h, 600);
  EXPECT_NEAR(m[0], 1.0 - std::exp(-7000.0 / 600), 1e-9);  // 7000 s at 1 m/min with τ 600 s
  // A travel that shrinks, or is not a path length, names the line and the column.
  auto refused = [&](const std::string& bad_row, const std::string& what) {
    WriteTextFile((dir / "temperature_log.csv").string(),
                  "time_s,date,coolant,x_travel_mm,t_nut_c\n0,d,off,500,25\n" + bad_row + "\n");
    try {
      LoadFitStates({}, (dir / "manifest.json").string());
      ADD_FAILURE() << "accepted: " << bad_row;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(":3:")) << e.what();
      EXPECT_THAT(e.what(), HasSubstr("x_travel_mm")) << e.what();
      EXPECT_THAT(e.what(), HasSubstr(what)) << e.what();
    }
  };
  refused("60,d,off,400,25", "only grows");
  refused("60,d,off,-3,25", "path length");
  refused("60,d,off,abc,25", "path length");
  fs::remove_all(dir);
}

// A synthetic axis whose thermal slope has a nut part and a motion part: states whose motion before
// and during the test differs from what the nut reads (as after machining stops), each with the
// logged travel of the axis.
constexpr double kNutGain = -0.006, kMotionGain = -0.004;  // µm/mm per °C, per m/min

std::vector<FitState> MotionStates(unsigned seed, double motion_gain, double tau_s, bool with_travel) {
  // Per state: the feed (mm/s) held for `hours` before the test and through it.
  struct Motion { double feed_mm_s, hours; };
  const std::vector<testing::TimedProfile> profiles = {
      {"cold", "off", 20, 0, 0},          {"warm-1", "off", 22, 0.002, 0},    {"warm-2", "off", 25, 0.001, 0},
      {"stop-1", "off", 27, -0.002, 0},   {"warm-3", "off", 23, 0.003, 0},    {"stop-2", "off", 24, -0.001, 0},
      {"busy-1", "off", 21, 0.001, 0},    {"busy-2", "off", 26, 0.0005, 0}};
  const std::vector<Motion> motion = {{0, 0}, {40, 1}, {10, 2}, {0, 0}, {60, 0.5}, {5, 3}, {80, 2}, {30, 0.2}};
  std::size_t state = 0;
  auto m_at = [&](double t) {  // the true M (m/min) at t: feed since −hours, exact first-order rise
    const Motion& mo = motion[state];
    const double since = t + mo.hours * 3600;
    return mo.hours > 0 ? mo.feed_mm_s * 0.06 * (1 - std::exp(-since / tau_s)) : 0.0;
  };
  auto states = testing::MakeTimedStates(profiles, 12, 0.1, seed, [&](const testing::TimedProfile& pr, double nut, double x, bool) {
    for (std::size_t i = 0; i < profiles.size(); ++i)
      if (profiles[i].label == pr.label) state = i;
    return (kNutGain * (nut - 20.0)) * (0.0 - x);  // the motion part is added below, with its time
  });
  for (std::size_t si = 0; si < states.size(); ++si) {
    state = si;
    auto& s = states[si];
    for (auto& p : s.measurement.points) p.deviation_um += motion_gain * m_at(*p.time_s) * (0.0 - p.target_mm);
    if (!with_travel) continue;
    // The log: a row every 30 s from 6 h before the start to past the end.
    const Motion& mo = motion[si];
    for (double t = -6 * 3600.0; t <= 1200; t += 30) {
      s.history.travel_time_s.push_back(t);
      const double moving_s = mo.hours > 0 ? std::max(0.0, t + mo.hours * 3600) : 0.0;
      s.history.travel_mm.push_back(mo.feed_mm_s * moving_s);
    }
  }
  return states;
}

TEST(MotionHeatFit, RecoversAKnownTimeConstantAndGain) {
  auto o = testing::TimedFitOptions();
  o.key_lag_grid_s = {0};
  o.motion_lag_grid_s = {300, 900, 1800, 3600};
  o.motion_heat = FitOptions::MotionHeat::kAuto;
  const auto states = MotionStates(5, kMotionGain, 900, true);
  const auto r = FitCompositeModel(states, o);
  const auto& a = r.model.axes.at(0);
  ASSERT_EQ(a.motion_lag_s, 900) << r.summary.axes[0].motion_reason;
  ASSERT_EQ(a.GainCount(), 2u);
  for (const auto& d : a.directions) {
    EXPECT_NEAR(d.thermal.at(0).k_um_per_mm_per_c[0], kNutGain, 0.05 * std::abs(kNutGain));
    EXPECT_NEAR(d.thermal.at(0).k_um_per_mm_per_c[1], kMotionGain, 0.05 * std::abs(kMotionGain));
    ASSERT_EQ(d.thermal.at(0).key_rise_range_c.size(), 2u);  // M's envelope too
  }
  EXPECT_THAT(r.summary.axes[0].motion_reason, HasSubstr("lowers the LOSO CV"));
  // The model predicts its own states to the noise, as the model without M cannot.
  o.motion_heat = FitOptions::MotionHeat::kOff;
  const auto without = FitCompositeModel(states, o);
  EXPECT_FALSE(without.model.axes[0].HasMotionHeat());
  for (const auto& s : states)
    if (s.label != "cold") {
      const auto lagged = LaggedKeyTemperatures(a, s.measurement, &s.history, s.coolant);
      double ss = 0;
      for (std::size_t i = 0; i < lagged.size(); ++i) {
        const auto& p = s.measurement.points[i];
        const auto pr = Predict(a, p.target_mm, p.direction,
                                {lagged[i].key_temp_c, lagged[i].ambient_c, s.coolant, true, lagged[i].motion_m_per_min});
        ss += std::pow(p.deviation_um - pr.total_um, 2);
      }
      EXPECT_LT(std::sqrt(ss / static_cast<double>(lagged.size())), 0.3) << s.label;
    }
}

TEST(MotionHeatFit, NotKeptWithoutMotionInTheDataNorTriedWithoutTravel) {
  auto o = testing::TimedFitOptions();
  o.key_lag_grid_s = {0};
  o.motion_heat = FitOptions::MotionHeat::kAuto;
  const auto none = FitCompositeModel(MotionStates(6, 0.0, 900, true), o);
  EXPECT_FALSE(none.model.axes[0].HasMotionHeat());
  EXPECT_THAT(none.summary.axes[0].motion_reason, HasSubstr("none: the best"));
  EXPECT_EQ(none.model.axes[0].directions[0].thermal[0].k_um_per_mm_per_c.size(), 1u);
  const auto no_log = FitCompositeModel(MotionStates(6, kMotionGain, 900, false), o);
  EXPECT_FALSE(no_log.model.axes[0].HasMotionHeat());
  EXPECT_THAT(no_log.summary.axes[0].motion_reason, HasSubstr("no travelled path of axis X"));
  // Off: not tried, and said (auto is the default, FitOptions::motion_heat).
  EXPECT_EQ(FitOptions{}.motion_heat, FitOptions::MotionHeat::kAuto);
  auto off_options = testing::TimedFitOptions();
  off_options.motion_heat = FitOptions::MotionHeat::kOff;
  const auto off = FitCompositeModel(MotionStates(6, kMotionGain, 900, true), off_options);
  EXPECT_FALSE(off.model.axes[0].HasMotionHeat());
  EXPECT_THAT(off.summary.axes[0].motion_reason, HasSubstr("off in the options"));
}

TEST(MotionHeatModel, PredictAddsItsTermAndTheFileRoundTripsAndRefusesBadValues) {
  AxisModel a = testing::OneKeyAxis(-0.01);
  a.motion_lag_s = 1800;
  for (auto& d : a.directions) {
    d.thermal[0].k_um_per_mm_per_c.push_back(-0.002);
    d.thermal[0].key_rise_range_c = {{-1, 10}, {0, 4}};
  }
  const double nut[1] = {25};
  const auto at = [&](double m) {
    return Predict(a, 500, Direction::kForward, {std::span<const double>(nut, 1), 20.0, CoolantState::kOff, true, m});
  };
  EXPECT_NEAR(at(0).thermal_um, -0.01 * 5 * -500, 1e-9);
  EXPECT_NEAR(at(3).thermal_um, (-0.01 * 5 - 0.002 * 3) * -500, 1e-9);
  EXPECT_FALSE(at(3).tan_beta_limited);
  EXPECT_TRUE(at(6).tan_beta_limited);  // beyond the fitted M: held and flagged
  EXPECT_NEAR(at(6).thermal_um, at(4).thermal_um, 1e-9);
  EXPECT_EQ(at(kNaN).thermal_um, 0);  // M unknown: geometric only, as a lost key
  // The bound covers the motion part (M at its fitted top).
  CompensationBoundOptions bo;
  bo.extra_rise_c = 0;
  AxisModel still = a;
  still.motion_lag_s = 0;
  for (auto& d : still.directions) d.thermal[0].k_um_per_mm_per_c.pop_back(), d.thermal[0].key_rise_range_c.pop_back();
  still.key_fitted_range_c = a.key_fitted_range_c = {{20, 30}};
  for (AxisModel* m : {&a, &still})
    for (auto& d : m->directions) d.geometric.center_mm = 500, d.geometric.half_span_mm = 500;  // travel 0–1000 mm
  EXPECT_GT(DeriveCompensationBound(a, bo).model_max_um, DeriveCompensationBound(still, bo).model_max_um + 1);

  CompositeModel m;
  m.machine = "T";
  m.axes.push_back(a);
  const std::string text = ModelToJson(m).dump();
  const auto back = ModelFromJson(nlohmann::json::parse(text), "m.json");
  EXPECT_EQ(back.axes[0].motion_lag_s, 1800);
  EXPECT_EQ(back.axes[0].directions[1].thermal[0].k_um_per_mm_per_c, a.directions[1].thermal[0].k_um_per_mm_per_c);
  EXPECT_THAT(text, HasSubstr("axis position every cycle"));  // the live input it needs, stated
  auto bad = [&](const std::function<void(nlohmann::json&)>& edit, const std::string& where) {
    auto j = nlohmann::json::parse(text);
    edit(j);
    try {
      ModelFromJson(j, "m.json");
      ADD_FAILURE() << "accepted: " << where;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(where));
    }
  };
  bad([](auto& j) { j["axes"][0]["motion_heat"]["tau_s"] = 0; }, "motion_heat.tau_s");
  bad([](auto& j) { j["axes"][0]["motion_heat"] = 5; }, "motion_heat");
  bad([](auto& j) { j["axes"][0].erase("motion_heat"); }, "k_um_per_mm_per_c");  // one gain too many then
}

// `predict` asks for the motion-heat input as it asks for a key temperature, says what it used, and
// `export` freezes it at rest unless given (and says so in the table's provenance).
TEST(MotionHeatCli, PredictAsksForTheInputAndExportFreezesItAtRest) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("trueaxis_motion_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  AxisModel a = testing::OneKeyAxis(-0.01);
  a.motion_lag_s = 1800;
  for (auto& d : a.directions) {
    d.geometric.center_mm = 500, d.geometric.half_span_mm = 500;
    d.thermal[0].k_um_per_mm_per_c.push_back(-0.002);
  }
  CompositeModel m;
  m.machine = "T";
  m.axes.push_back(a);
  const std::string model = (dir / "m.json").string();
  WriteTextFile(model, ModelToJson(m).dump(2));
  const std::string point = "predict --model " + model + " --axis X --position-mm 500 --direction + --temp nut=25 --ambient-c 20";
  const auto missing = ::trueaxis::testing::RunCli(point);
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("--motion-m-per-min"));
  const auto given = ::trueaxis::testing::RunCli(point + " --motion-m-per-min 3 --json");
  ASSERT_EQ(given.exit_code, 0) << given.output;
  const auto j = nlohmann::json::parse(given.output);
  EXPECT_NEAR(j["thermal_um"].get<double>(), (-0.01 * 5 - 0.002 * 3) * -500, 1e-6);
  EXPECT_EQ(j["motion_m_per_min"].get<double>(), 3);
  const auto table = ::trueaxis::testing::RunCli("export --model " + model + " --axis X --format csv --temp nut=25 --temp ambient=20 --out " +
                                                 (dir / "t.csv").string());
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_THAT(ReadTextFile((dir / "t.csv").string()), HasSubstr("motion_m_per_min=0 (at rest)"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::model
