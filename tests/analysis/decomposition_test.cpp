#include "trueaxis/analysis/decomposition.hpp"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "test_util.hpp"

using namespace trueaxis;
using analysis::Decompose;
using analysis::DecompositionOptions;

namespace {
constexpr double kPi = std::numbers::pi;

// Known error: 2 µm + 50 µm/m, 1.5 µm first and 0.4 µm second harmonic of a
// 10 mm lead, run-to-run noise σ.
measure::Measurement Synthetic(double step_mm, double span_mm, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  std::vector<double> x;
  std::vector<std::vector<double>> up, down;
  for (double t = 0; t <= span_mm + 1e-9; t += step_mm) {
    x.push_back(t);
    const double sys = 2 + 0.05 * t + 1.5 * std::sin(2 * kPi * t / 10 + 0.3) + 0.4 * std::sin(2 * kPi * 2 * t / 10 - 1);
    up.emplace_back(), down.emplace_back();
    for (int j = 0; j < 5; ++j) up.back().push_back(sys + noise(rng)), down.back().push_back(sys + noise(rng));
  }
  return trueaxis::testing::MakeMeasurement(x, up, down);
}
}  // namespace

TEST(Decompose, RecoversTrendHarmonicsAndSigma) {
  const auto ev = analysis::Evaluate(Synthetic(1.0, 100, 0.1, 7));
  DecompositionOptions o;
  o.lead_mm = 10;
  o.harmonics = 2;
  const auto d = Decompose(ev, o);
  ASSERT_EQ(d.harmonics.size(), 2u);
  ASSERT_TRUE(d.harmonics[0].resolved);
  ASSERT_TRUE(d.harmonics[1].resolved);
  EXPECT_NEAR(d.harmonics[0].amplitude_um, 1.5, 0.05);
  EXPECT_NEAR(d.harmonics[0].phase_rad, 0.3, 0.05);
  EXPECT_NEAR(d.harmonics[1].amplitude_um, 0.4, 0.05);
  EXPECT_NEAR(d.harmonics[1].phase_rad, -1.0, 0.15);
  ASSERT_EQ(d.trend_coefficients.size(), 2u);
  EXPECT_NEAR(d.trend_coefficients[0], 2, 0.05);
  EXPECT_NEAR(d.trend_coefficients[1], 0.05, 0.001);
  EXPECT_NEAR(d.sigma_um, 0.1, 0.02);
  EXPECT_LT(d.residual_rms_um, 0.1);
  // The parts add up to the fitted means.
  for (const auto& p : d.points) EXPECT_NEAR(p.progressive_um + p.periodic_um + p.residual_um, p.mean_um, 1e-9);
  EXPECT_TRUE(d.notes.empty());
}

TEST(Decompose, CoarseTargetsSayAliasedInsteadOfInventingHarmonics) {
  // 25 mm spacing cannot see a 10 mm lead.
  const auto ev = analysis::Evaluate(Synthetic(25.0, 500, 0.1, 3));
  DecompositionOptions o;
  o.lead_mm = 10;
  const auto d = Decompose(ev, o);
  EXPECT_FALSE(d.periodic_fitted());
  for (const auto& h : d.harmonics) {
    EXPECT_FALSE(h.resolved);
    EXPECT_EQ(h.amplitude_um, 0);
    EXPECT_NE(h.note.find("aliased"), std::string::npos) << h.note;
  }
  ASSERT_FALSE(d.notes.empty());
  EXPECT_NE(d.notes.back().find("aliased"), std::string::npos);
  EXPECT_EQ(d.Periodic(12.3), 0);
  // The trend is still there: 50 µm/m.
  EXPECT_NEAR(d.trend_coefficients[1], 0.05, 0.01);
}

TEST(Decompose, HarmonicBelowNyquistIsKeptHigherOneDropped) {
  // 3 mm spacing: the 10 mm period (needs < 5) is resolved, the 5 mm one (needs < 2.5) is not.
  const auto ev = analysis::Evaluate(Synthetic(3.0, 120, 0.05, 5));
  DecompositionOptions o;
  o.lead_mm = 10;
  const auto d = Decompose(ev, o);
  EXPECT_TRUE(d.harmonics[0].resolved);
  EXPECT_FALSE(d.harmonics[1].resolved);
}

TEST(Decompose, WithoutLeadOnlyTrendAndNote) {
  const auto ev = analysis::Evaluate(Synthetic(5.0, 100, 0.1, 1));
  const auto d = Decompose(ev, DecompositionOptions{});
  EXPECT_TRUE(d.harmonics.empty());
  ASSERT_EQ(d.notes.size(), 1u);
  EXPECT_NE(d.notes[0].find("lead"), std::string::npos);
}

TEST(Decompose, TooFewTargetsReduceTheModel) {
  auto m = trueaxis::testing::MakeMeasurement({0, 1}, {{1, 2}, {3, 4}}, {{1, 2}, {3, 4}});
  const auto ev = analysis::Evaluate(m);
  DecompositionOptions o;
  o.lead_mm = 10;
  o.trend_degree = 3;
  const auto d = Decompose(ev, o);
  EXPECT_EQ(d.trend_coefficients.size(), 2u);  // reduced to a line through 2 points
  EXPECT_FALSE(d.periodic_fitted());           // no degrees of freedom left for harmonics
  EXPECT_NEAR(d.points[0].residual_um, 0, 1e-9);
}

TEST(DecompositionOptions, Validates) {
  DecompositionOptions o;
  std::string why;
  EXPECT_TRUE(o.IsValid(&why));
  o.lead_mm = -1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("lead_mm"), std::string::npos);
  o = {};
  o.trend_degree = 7;
  EXPECT_FALSE(o.IsValid(&why));
  const auto ev = analysis::Evaluate(Synthetic(5.0, 50, 0.1, 1));
  EXPECT_THROW(Decompose(ev, o), std::invalid_argument);
}
