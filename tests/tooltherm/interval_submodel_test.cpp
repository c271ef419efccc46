// Seed 001's interval sub-models: the hysteresis form (rise since the interval began), the
// training-range clamp and the held-out fallback to the one curve (docs/tool-thermal.md, "Models").
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/tooltherm/tool_error_model.hpp"

namespace trueaxis::tooltherm {
namespace {

// A two-body tool: Tv sees the fast body; the error follows fast and slow (τ 15 min). Blocks of
// heating towards `targets_c[i]` and cooling back to 20 °C, `block_s` each, sampled every 5 s.
std::vector<ToolRecord> TwoBodyCourse(const std::vector<double>& targets_c, double block_s, double noise_c, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, noise_c);
  std::vector<ToolRecord> rows;
  double fast = 20, slow = 20, t = 0;
  for (double target_c : targets_c)
    for (double goal : {target_c, 20.0})
      for (double end = t + block_s; t < end; t += 5) {
        fast += (goal - fast) * (1 - std::exp(-5.0 / 120));
        slow += (fast - slow) * (1 - std::exp(-5.0 / 900));
        rows.push_back({t, fast + noise(rng), -(0.3 * (fast - 20) + 0.9 * (slow - 20)), rows.empty()});
      }
  return rows;
}

double Rms(const ToolErrorModel& m, ToolModelKind k, const std::vector<ToolRecord>& rows) {
  const auto p = PredictSeries(m, k, rows);
  double s = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) s += std::pow(p[i] - rows[i].error_um, 2);
  return std::sqrt(s / static_cast<double>(rows.size()));
}

TEST(IntervalSubModels, BeatOneCurveOnAnotherDayOfAKnownHysteresis) {
  // Trained on blocks to 30…50 °C, tested on other heights and durations: the branches start
  // from other states than in training, which an absolute curve per interval cannot know.
  const ToolErrorModel m = FitToolErrorModel(1, TwoBodyCourse({45, 30, 50, 38, 25, 42}, 3600, 0.1, 1), 20);
  const auto test = TwoBodyCourse({35, 48, 28, 44}, 2700, 0.1, 2);
  const double one = Rms(m, ToolModelKind::kOne, test), sub = Rms(m, ToolModelKind::kIntervals, test);
  EXPECT_GT(m.interval[2].weight, 0.5);  // held-out data confirmed the cooling branch
  EXPECT_LT(sub, 0.7 * one) << "sub-models " << sub << " µm vs one curve " << one << " µm";
  // Cooling starts from other heights each time: its branch uses the rise since it began.
  // (Heating always starts from 20 °C here, so its rise is Tv again and is left out.)
  EXPECT_TRUE(m.interval_fitted[2]);
  EXPECT_NE(m.interval[2].per_c_since_start_um, 0.0);
  EXPECT_EQ(m.interval[0].per_c_since_start_um, 0.0);
  // Stored with the tool and read back, the same predictions.
  const ToolErrorModel back = ToolErrorModel::FromJson(m.ToJson(), "m.json");
  EXPECT_EQ(PredictSeries(back, ToolModelKind::kIntervals, test), PredictSeries(m, ToolModelKind::kIntervals, test));
  nlohmann::json j = m.ToJson();
  j["intervals"][2]["weight"] = 1.5;
  EXPECT_THROW(ToolErrorModel::FromJson(j, "m.json"), InputError);
}

TEST(IntervalSubModels, OutsideTheirTrainingRangeTheyFollowTheOneCurve) {
  ToolErrorModel m;
  m.one = {0, -1.0};
  m.classifier = {20, 30, 10};
  m.interval_fitted = {true, true, true};
  for (auto& it : m.interval) {  // a steeper curve, trained on 25…30 °C only
    it.line = {2.0, -3.0};
    it.tv_from_c = 25;
    it.tv_to_c = 30;
  }
  ToolErrorPredictor p(m, ToolModelKind::kIntervals);
  double t = 0;
  p.Push(t, 20, true);
  ThermalInterval k = ThermalInterval::kStartUp;
  double tv = 20, e = 0;
  while (k == ThermalInterval::kStartUp || tv < 60) {  // heat at 2 °C/s, far beyond 30 °C
    tv += 2;
    e = p.Push(t += 1, tv, false);
    k = p.interval();
  }
  ASSERT_EQ(k, ThermalInterval::kHeating);
  // Difference from the one curve held at its value at 30 °C: (2 − 0) + (−3 + 1)·10 = −18 µm.
  EXPECT_NEAR(e, -1.0 * (tv - 20) - 18.0, 1e-9) << "at Tv " << tv;
}

TEST(IntervalSubModels, FallBackToTheOneCurveWhenTheyDoNotPredictHeldOutDataBetter) {
  // The error is one straight line in Tv plus noise: no hysteresis to find. Whatever the
  // sub-models fit is noise, which held-out data shows: their weight goes to 0 (the one curve
  // stands in, with a warning) or near it.
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.5);
  auto course = TwoBodyCourse({45, 30, 50, 38}, 3600, 0.1, 3);
  for (auto& r : course) r.error_um = -1.2 * (r.tv_c - 20) + noise(rng);
  std::vector<std::string> warnings;
  const ToolErrorModel m = FitToolErrorModel(1, course, 20, &warnings);
  int fell_back = 0;
  for (int k = 0; k < 3; ++k) {
    EXPECT_GT(m.interval[k].cv_rows, 0) << k;
    if (!m.interval_fitted[k]) ++fell_back;
    else EXPECT_LT(m.interval[k].weight, 0.5) << k;  // what is kept of a noise fit is a small share
  }
  EXPECT_GE(fell_back, 2);
  EXPECT_GE(warnings.size(), static_cast<std::size_t>(fell_back));
  const auto test = TwoBodyCourse({35, 48}, 2700, 0.1, 4);
  EXPECT_LT(Rms(m, ToolModelKind::kIntervals, test), 1.05 * Rms(m, ToolModelKind::kOne, test));
}

}  // namespace
}  // namespace trueaxis::tooltherm
