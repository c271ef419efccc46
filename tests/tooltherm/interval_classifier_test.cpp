#include "trueaxis/tooltherm/interval_classifier.hpp"

#include <random>

#include <gtest/gtest.h>

namespace trueaxis::tooltherm {
namespace {

// Ramp up 0→40 min at +30 °C/h, hold 40→80 min, ramp down 80→120 min, hold to 160 min.
double Profile(double t_s) {
  const double m = t_s / 60.0;
  if (m < 40) return 20 + 30.0 * m / 60.0;
  if (m < 80) return 40;
  if (m < 120) return 40 - 30.0 * (m - 80) / 60.0;
  return 20;
}

struct Course {
  std::vector<double> t, tv;
  std::vector<bool> restart;
};

Course Sample(double dt_s, double noise_c, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0, noise_c);
  Course r;
  for (double t = 0; t <= 160 * 60; t += dt_s) {
    r.t.push_back(t);
    r.tv.push_back(Profile(t) + (noise_c > 0 ? n(rng) : 0.0));
    r.restart.push_back(r.t.size() == 1);
  }
  return r;
}

int Switches(const std::vector<ThermalInterval>& c) {
  int n = 0;
  for (std::size_t i = 1; i < c.size(); ++i)
    if (c[i] != c[i - 1] && c[i - 1] != ThermalInterval::kStartUp) ++n;
  return n;
}

ThermalInterval At(const Course& r, const std::vector<ThermalInterval>& c, double minute) {
  std::size_t i = 0;
  while (i + 1 < r.t.size() && r.t[i + 1] <= minute * 60) ++i;
  return c[i];
}

void ExpectClassifies(double dt_s, double noise_c) {
  SCOPED_TRACE(testing::Message() << "dt " << dt_s << " s, noise " << noise_c << " °C");
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const Course r = Sample(dt_s, noise_c, seed);
    // Options from the data alone (window, dead band, dwell).
    const ToolClassifierOptions o = ChooseClassifierOptions(r.t, r.tv, r.restart);
    const auto c = ClassifySeries(r.t, r.tv, r.restart, o);
    EXPECT_EQ(At(r, c, 30), ThermalInterval::kHeating) << o.window_s << " s window";
    EXPECT_EQ(At(r, c, 70), ThermalInterval::kSteady);
    EXPECT_EQ(At(r, c, 110), ThermalInterval::kCooling);
    EXPECT_EQ(At(r, c, 155), ThermalInterval::kSteady);
    // heating → steady → cooling → steady: four changes at most, no chatter.
    EXPECT_LE(Switches(c), 4);
  }
}

TEST(IntervalClassifier, CleanRamps) { ExpectClassifies(2, 0); }
TEST(IntervalClassifier, NoisyRamps) { ExpectClassifies(2, 0.5); }
TEST(IntervalClassifier, CoarseSampleInterval) { ExpectClassifies(60, 0.3); }
TEST(IntervalClassifier, CoarseAndNoisy) { ExpectClassifies(30, 1.0); }

TEST(IntervalClassifier, MeasuresSampleIntervalAndNoise) {
  const Course r = Sample(5, 0.8, 7);
  const SeriesStatistics s = SeriesStatisticsOf(r.t, r.tv);
  EXPECT_NEAR(s.sample_s, 5, 1e-9);
  EXPECT_NEAR(s.noise_c, 0.8, 0.15);
}

TEST(IntervalClassifier, DwellStopsChatterThatTheBareThresholdShows) {
  // Steady with noise right at the dead band: the bare trend rule flips, the dwell holds.
  const Course r = Sample(2, 0.5, 3);
  ToolClassifierOptions o = ClassifierOptionsFor(SeriesStatisticsOf(r.t, r.tv), 5, 0);
  o.dead_band_c_per_h = NoiseSlopeCPerH(SeriesStatisticsOf(r.t, r.tv), o.window_s);  // 1σ: flips often
  ToolClassifierOptions no_dwell = o;
  no_dwell.dwell_s = 0;
  const auto with = ClassifySeries(r.t, r.tv, r.restart, o);
  const auto without = ClassifySeries(r.t, r.tv, r.restart, no_dwell);
  EXPECT_GT(Switches(without), 3 * Switches(with) + 10);
}

TEST(IntervalClassifier, RestartForgetsTheOldToolsCourse) {
  Course r = Sample(2, 0, 1);
  const ToolClassifierOptions o = ClassifierOptionsFor(SeriesStatisticsOf(r.t, r.tv), 10, 4.0);
  r.restart[r.t.size() / 2] = true;
  const auto c = ClassifySeries(r.t, r.tv, r.restart, o);
  EXPECT_EQ(c[r.t.size() / 2], ThermalInterval::kStartUp);
}

}  // namespace
}  // namespace trueaxis::tooltherm
