// DiagnoseResidual (fit_diagnostics.hpp): a slope, an offset or only noise in every state's
// residual, and the key sensors' shares of the thermal correction.
#include <cmath>
#include <random>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "trueaxis/modelfit/fit_diagnostics.hpp"

namespace trueaxis::model {
namespace {

using ::testing::HasSubstr;

// Seven states over a 0..800 mm travel, 17 targets × 2 directions; residual = offset + slope·x
// + Gaussian noise σ; two keys whose corrections scale with `gain_a`, `gain_b`.
ResidualDiagnosisInput States(double offset_um, double slope_um_per_m, double sigma_um, unsigned seed,
                              bool alternate_offset_sign = false) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_um);
  ResidualDiagnosisInput in;
  in.key_sensors = {"nut", "bearing"};
  for (int s = 0; s < 7; ++s) {
    StateResidualInput st;
    st.label = "warm-" + std::to_string(s + 1);
    st.key_contribution_um.resize(2);
    const double off = alternate_offset_sign && s % 2 ? -offset_um : offset_um;
    for (int dir = 0; dir < 2; ++dir)
      for (int i = 0; i <= 16; ++i) {
        const double x = 50.0 * i;
        st.position_mm.push_back(x);
        st.residual_um.push_back(off + slope_um_per_m * (x - 400) / 1000 + noise(rng));
        st.key_contribution_um[0].push_back(3.0 * (s + 1) * x / 800);
        st.key_contribution_um[1].push_back(1.0 * (s + 1) * x / 800);
      }
    in.states.push_back(st);
  }
  return in;
}

TEST(FitDiagnostics, APureSlopeInEveryStateIsNamedAndTheStructureSensorSuggested) {
  const auto d = DiagnoseResidual(States(0.0, 10.0, 0.5, 1));  // 8 µm end to end over 800 mm
  ASSERT_EQ(d.states.size(), 7u);
  for (const auto& s : d.states) {
    EXPECT_NEAR(s.slope_um_per_m, 10.0, 1.0) << s.label;
    EXPECT_NEAR(s.end_to_end_um, 8.0, 0.8) << s.label;
    EXPECT_NEAR(s.offset_um, 0.0, 0.3) << s.label;
    EXPECT_NEAR(s.pattern_rms_um, 0.5, 0.15) << s.label;
  }
  EXPECT_TRUE(d.slope_structure);
  EXPECT_FALSE(d.offset_structure);
  ASSERT_FALSE(d.findings.empty());
  EXPECT_THAT(d.findings[0], HasSubstr("slope"));
  EXPECT_THAT(d.findings[0], HasSubstr("between the fixed bearing and the measuring point"));
  EXPECT_THAT(ResidualDiagnosisBrief(d), HasSubstr("in-sample"));
}

TEST(FitDiagnostics, PureNoiseClaimsNoStructure) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    const auto d = DiagnoseResidual(States(0.0, 0.0, 2.0, seed));
    EXPECT_FALSE(d.slope_structure) << seed;
    EXPECT_FALSE(d.offset_structure) << seed;
    ASSERT_EQ(d.findings.size(), 1u);
    EXPECT_THAT(d.findings[0], HasSubstr("no structure"));
  }
}

TEST(FitDiagnostics, AnOffsetInEveryStatePointsToTheRoomOrColumn) {
  const auto same = DiagnoseResidual(States(3.0, 0.0, 0.5, 2));
  EXPECT_TRUE(same.offset_structure);
  EXPECT_FALSE(same.slope_structure);
  ASSERT_EQ(same.findings.size(), 1u);
  EXPECT_THAT(same.findings[0], HasSubstr("room/ambient sensor"));
  EXPECT_THAT(same.findings[0], HasSubstr("same sign"));
  for (const auto& s : same.states) EXPECT_NEAR(s.offset_um, 3.0, 0.3);

  const auto changing = DiagnoseResidual(States(3.0, 0.0, 0.5, 3, true));
  EXPECT_TRUE(changing.offset_structure);
  EXPECT_THAT(changing.findings[0], HasSubstr("changing from state to state"));
}

TEST(FitDiagnostics, ASlopeOfChangingSignIsNotCalledAStructureButNamed) {
  auto in = States(0.0, 10.0, 0.5, 6);
  for (std::size_t i = 0; i < in.states.size(); i += 2)
    for (auto& r : in.states[i].residual_um) r = -r;  // every other state tilts the other way
  const auto d = DiagnoseResidual(in);
  EXPECT_FALSE(d.slope_structure);
  ASSERT_EQ(d.findings.size(), 1u);
  EXPECT_THAT(d.findings[0], HasSubstr("slope of changing sign"));
}

TEST(FitDiagnostics, KeySharesSumToOneHundredAndFollowTheLargerCorrection) {
  const auto d = DiagnoseResidual(States(0.0, 0.0, 1.0, 4));
  ASSERT_EQ(d.key_shares.size(), 2u);
  EXPECT_NEAR(d.key_shares[0].share_pct + d.key_shares[1].share_pct, 100.0, 1e-9);
  // nut's correction is 3× bearing's at every point: 9/10 of the mean square.
  EXPECT_NEAR(d.key_shares[0].share_pct, 90.0, 1e-6);
  EXPECT_NEAR(d.key_shares[0].rms_um, 3 * d.key_shares[1].rms_um, 1e-9);
}

TEST(FitDiagnostics, ColdStatesAreShownButNotJudged) {
  auto in = States(0.0, 10.0, 0.5, 5);
  in.states.resize(3);
  for (std::size_t i = 0; i < 5; ++i) {  // five cold states with no slope: the three heated still decide
    auto c = in.states[0];
    c.label = "cold-" + std::to_string(i);
    c.cold = true;
    for (auto& r : c.residual_um) r = 0.0;
    in.states.push_back(c);
  }
  const auto d = DiagnoseResidual(in);
  EXPECT_TRUE(d.slope_structure);
  EXPECT_TRUE(d.states.back().cold);
}

}  // namespace
}  // namespace trueaxis::model
