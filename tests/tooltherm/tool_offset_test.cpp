#include "trueaxis/tooltherm/tool_offset.hpp"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/median.hpp"
#include "trueaxis/tooltherm/tool_evaluation.hpp"
#include "trueaxis/tooltherm/tool_fallback.hpp"

namespace trueaxis::tooltherm {
namespace {

ToolErrorModel Constant(int tool, double error_um) {
  ToolErrorModel m;
  m.tool = tool;
  m.one = {error_um, 0};
  m.interval_fitted = {false, false, false};
  m.lag = m.one;
  m.two_body_intercept_um = error_um;
  return m;
}

TEST(ToolOffset, AToolChangeSwitchesTheModelAndRampsNeverJumps) {
  ToolOffsetOptions o;
  o.max_rate_um_per_s = 2.0;
  ToolOffsetCompensator comp({{1, Constant(1, -30)}, {2, Constant(2, +10)}}, ToolModelKind::kOne, o);
  double t = 0, last = 0;
  ToolOffsetCycle c;
  for (int i = 0; i < 40; ++i, t += 1) {  // tool 1 settles at +30 µm correction
    c = comp.Cycle(t, 1, 25);
    EXPECT_LE(std::abs(c.applied_correction_um - last), 2.0 + 1e-9);
    last = c.applied_correction_um;
  }
  EXPECT_NEAR(c.applied_correction_um, 30, 0.1);
  int ramp_cycles = 0;
  for (int i = 0; i < 40; ++i, t += 1) {  // tool change: model of tool 2, ramp to −10 µm
    c = comp.Cycle(t, 2, 25);
    EXPECT_DOUBLE_EQ(c.desired_correction_um, -10);
    EXPECT_LE(std::abs(c.applied_correction_um - last), 2.0 + 1e-9) << "cycle " << i;
    if (c.limited) ++ramp_cycles;
    last = c.applied_correction_um;
  }
  EXPECT_NEAR(c.applied_correction_um, -10, 0.1);
  EXPECT_GE(ramp_cycles, 18);  // 40 µm at 2 µm/s
  // An unknown tool ramps to 0 and says so.
  c = comp.Cycle(t, 7, 25);
  EXPECT_TRUE(c.unmodelled);
  EXPECT_NEAR(c.applied_correction_um, -8, 1e-9);
}

TEST(ToolOffset, ExportsALinuxCncToolTableLineAndG10) {
  ToolDescription t;
  t.number = 4;
  t.name = "drill";
  t.diameter_mm = 8;
  EXPECT_EQ(LinuxCncToolTableLine(t, 150, 12.34), "T4 P4 Z+150.0123 D+8.0000 ;drill thermal +12.3 um");
  EXPECT_EQ(G10ToolOffsetCommand(4, 150, -5), "G10 L1 P4 Z149.9950 (thermal -5.0 um)\nG43 H4");
}

TEST(ToolModels, SubModelsBeatOneCurveOnATwoBodyHysteresis) {
  // Synthetic two-body tool: Tv sees a fast body, the error follows fast + slow (τ 15 min).
  std::vector<ToolRecord> rows;
  double fast = 20, slow = 20;
  for (int i = 0; i < 3 * 3600 / 5; ++i) {
    const double t = i * 5.0;
    const double target = std::fmod(t, 7200) < 3600 ? 45 : 20;  // 1 h heating, 1 h cooling
    fast += (target - fast) * (1 - std::exp(-5.0 / 120));
    slow += (fast - slow) * (1 - std::exp(-5.0 / 900));
    rows.push_back({t, fast, -(0.3 * (fast - 20) + 0.9 * (slow - 20)), i == 0});
  }
  const ToolErrorModel m = FitToolErrorModel(1, rows, 20);
  auto rms = [&](ToolModelKind k) {
    const auto p = PredictSeries(m, k, rows);
    double s = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) s += std::pow(p[i] - rows[i].error_um, 2);
    return std::sqrt(s / rows.size());
  };
  EXPECT_LT(rms(ToolModelKind::kIntervals), 0.7 * rms(ToolModelKind::kOne));
  EXPECT_LT(rms(ToolModelKind::kTwoBody), 0.05 * rms(ToolModelKind::kNone));  // the true structure
  const ToolErrorModel back = ToolErrorModel::FromJson(m.ToJson(), "m.json");
  EXPECT_EQ(PredictSeries(back, ToolModelKind::kIntervals, rows), PredictSeries(m, ToolModelKind::kIntervals, rows));
}

TEST(ToolDay, SameSeedSameDayAndTheCompensationHelps) {
  ToolTable table = RandomToolTable(2, 4);
  ToolDayOptions o;
  o.hours = 1.5;
  o.sample_s = 5;
  o.sensor = TvSensor::kPyrometer;
  const ToolDayRecording a = RunToolDay(table, o), b = RunToolDay(table, o);
  ASSERT_EQ(a.samples.size(), b.samples.size());
  EXPECT_EQ(a.samples.back().tv_c, b.samples.back().tv_c);
  o.seed = 2;
  const ToolEvaluation ev = EvaluateToolModels(table, a, RunToolDay(table, o));
  for (const auto& sc : ev.tools)
    if (sc.samples > 50) EXPECT_LT(sc.rms_um[static_cast<std::size_t>(ToolModelKind::kIntervals)], sc.rms_um[0]) << sc.tool;
}

// A tool that did not cut on its training day gets a stand-in from the other
// tools scaled by its geometry, flagged, and it compensates most of that
// tool's error on another day; alone, a tool gets no model and a warning.
TEST(ToolModels, AToolWithoutTrainingGetsAFlaggedStandInFromTheOthers) {
  const ToolTable table = RandomToolTable(3, 7);
  ToolDayOptions o;
  o.hours = 4;
  o.sample_s = 5;
  o.program = ToolDayProgramKind::kBlocks;
  o.sensor = TvSensor::kPyrometer;
  ToolDayRecording training = RunToolDay(table, o);
  const int missing = table.tools[1].number;
  std::erase_if(training.samples, [&](const ToolDaySample& s) { return s.tool == missing; });
  o.seed = 2;
  const ToolDayRecording test = RunToolDay(table, o);

  std::vector<std::string> warnings;
  const auto models = FitToolModels(table, training, &warnings);
  ASSERT_TRUE(models.count(missing));
  const ToolErrorModel& stand_in = models.at(missing);
  std::vector<int> own;  // the tools fitted on their own data
  for (const auto& [number, m] : models)
    if (m.fallback_from_tools.empty()) own.push_back(number);
  ASSERT_FALSE(own.empty());
  EXPECT_EQ(stand_in.fallback_from_tools, own);
  EXPECT_EQ(stand_in.training_rows, 0);
  bool warned = false;
  for (const auto& w : warnings) warned |= w.find("stand-in") != std::string::npos && w.find(std::to_string(missing)) != std::string::npos;
  EXPECT_TRUE(warned);
  // Scaled by the gauge length's free growth: the slope per µm of growth is the others' median.
  std::vector<double> ratios;
  for (int number : own) ratios.push_back(models.at(number).one.per_c_um / GaugeGrowthUmPerC(*table.Find(number)));
  std::sort(ratios.begin(), ratios.end());
  const std::size_t n = ratios.size();
  const double median = n % 2 ? ratios[n / 2] : 0.5 * (ratios[n / 2 - 1] + ratios[n / 2]);
  EXPECT_NEAR(stand_in.one.per_c_um, median * GaugeGrowthUmPerC(table.tools[1]), 1e-12);
  // `best` is a zones stand-in: the others' whole zone slope per µm of free growth, spread over
  // this tool's zones by their free growth, and the others' median zones intercept.
  EXPECT_EQ(stand_in.best, ToolModelKind::kZones);
  std::vector<double> zone_ratios, zone_intercepts;
  for (int number : own) {
    const ToolErrorModel& m = models.at(number);
    double slope = 0;
    for (double b : m.zone_um_per_c) slope += b;
    zone_ratios.push_back(slope / GaugeGrowthUmPerC(*table.Find(number)));
    zone_intercepts.push_back(m.zone_intercept_um);
  }
  const std::vector<double> g = ZoneGrowthUmPerC(table.tools[1]);
  ASSERT_EQ(stand_in.zone_um_per_c.size(), g.size());
  for (std::size_t z = 0; z < g.size(); ++z) EXPECT_NEAR(stand_in.zone_um_per_c[z], Median(zone_ratios) * g[z], 1e-12);
  EXPECT_NEAR(stand_in.zone_intercept_um, Median(zone_intercepts), 1e-12);

  const ToolEvaluation ev = EvaluateToolModels(table, training, test);
  for (const auto& sc : ev.tools)
    if (sc.tool == missing) {
      ASSERT_GT(sc.samples, 50);
      EXPECT_LT(sc.rms_um[static_cast<std::size_t>(ToolModelKind::kBest)], 0.5 * sc.rms_um[0]);
    }

  // The flag survives the model file; a broken flag is refused naming the field.
  const ToolErrorModel back = ToolErrorModel::FromJson(stand_in.ToJson(), "models.json");
  EXPECT_EQ(back.fallback_from_tools, stand_in.fallback_from_tools);
  nlohmann::json bad = stand_in.ToJson();
  bad["fallback_from_tools"] = {0};
  try {
    ToolErrorModel::FromJson(bad, "models.json");
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "fallback_from_tools");
  }

  // Alone on its day: nothing to build a stand-in from.
  ToolTable alone;
  alone.tools = {table.tools[1]};
  warnings.clear();
  EXPECT_TRUE(FitToolModels(alone, training, &warnings).empty());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("not compensated"), std::string::npos);
}

}  // namespace
}  // namespace trueaxis::tooltherm

namespace trueaxis::tooltherm {
namespace {

TEST(ToolModels, ABadModelFileNamesTheField) {
  ToolErrorModel m;
  m.tool = 3;
  nlohmann::json j = m.ToJson();
  j["classifier"].erase("dwell_s");
  try {
    ToolErrorModel::FromJson(j, "models.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "classifier.dwell_s");
  }
  j = m.ToJson();
  j["best"] = "magic";
  EXPECT_THROW(ToolErrorModel::FromJson(j, "models.json"), InputError);
  j = m.ToJson();
  j["lag"]["tau_s"] = -1;
  EXPECT_THROW(ToolErrorModel::FromJson(j, "models.json"), InputError);
}

TEST(ToolModels, BestUsesTheZoneMeansWhenGivenAndTheTvChoiceOtherwise) {
  ToolErrorModel m;
  m.one = {1, 0};
  m.lag = {2, 0};
  m.zone_intercept_um = 5;
  m.zone_um_per_c = {0, 0};
  m.best = ToolModelKind::kZones;
  m.best_without_zones = ToolModelKind::kLag;
  ToolErrorPredictor p(m, ToolModelKind::kBest);
  const std::vector<double> zones = {30, 40};
  EXPECT_DOUBLE_EQ(p.Push(0, 25, true, zones), 5);
  EXPECT_DOUBLE_EQ(p.Push(1, 25, false), 2);  // no zone means: the Tv models' choice
}

}  // namespace
}  // namespace trueaxis::tooltherm
