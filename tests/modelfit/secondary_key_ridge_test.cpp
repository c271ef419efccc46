// FitOptions::secondary_key_ridge (issue 10): the gains of the keys after the first are shrunk
// toward the single-key fit, so two keys that rose together over the calibration cannot take large
// gains of opposite sign that swing on a working day's other mix of readings.
#include <cmath>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/modelfit/model_fit.hpp"

namespace trueaxis::model {
namespace {

using testing::SyntheticMachine;
using ::testing::HasSubstr;

// The error follows the screw's temperature S, which no sensor reads. The nut reads S plus a
// transient 1.5·d, the bearing 0.7·(S + d) + e: over the calibration d ≈ 0.3·S (the two keys rise
// together), so nut and bearing together reconstruct S only through their small difference —
// plain least squares finds it with gains of opposite sign. `e` is a bearing heat the calibration
// never showed (0 there).
struct HiddenScrew {
  SyntheticMachine sm;
  HiddenScrew() {
    sm.k_nut = -0.006;  // µm/mm/°C of S
    sm.k_bearing = 0;
    sm.px_mm = 0;
    sm.noise_um = 0.05;
  }
  FitState State(const std::string& label, double s_c, double d_c, double e_c, std::mt19937& rng) const {
    auto m = sm.Make({label, s_c, 0, 0, 0}, rng, /*with_motor=*/false);
    for (auto& p : m.points) {  // temperatures {nut, bearing, ambient}
      const double amb = p.temperatures_c[2];
      p.temperatures_c[0] += 1.5 * d_c;
      p.temperatures_c[1] = amb + 0.7 * (s_c + d_c) + e_c;
    }
    return MakeFitState(m);
  }
  std::vector<FitState> Calibration() const {
    std::mt19937 rng(11);
    std::vector<FitState> out{State("cold", 0, 0, 0, rng)};
    const double s[] = {1, 2, 3, 4, 5, 6};
    const double delta[] = {0.04, -0.05, 0.06, -0.03, 0.05, -0.06};  // d − 0.3·S: what tells S apart
    for (int i = 0; i < 6; ++i)
      out.push_back(State("heated-" + std::to_string(i + 1), s[i], 0.3 * s[i] + delta[i], 0, rng));
    return out;
  }
  FitResult Fit(double ridge) const {
    FitOptions o;
    o.key_sensors = {"nut", "bearing"};
    o.secondary_key_ridge = ridge;
    o.ambient_sensor = "none";
    return FitCompositeModel(Calibration(), o);
  }
  // RMS of measured − predicted over a held-out state.
  static double HeldOutRms(const FitResult& r, const FitState& st) {
    const auto res = PredictionResidual(r.model.axes[0], st.measurement, CoolantState::kOff);
    double ss = 0;
    for (const auto& p : res.points) ss += p.deviation_um * p.deviation_um;
    return std::sqrt(ss / static_cast<double>(res.points.size()));
  }
};

TEST(SecondaryKeyRidge, PlainLeastSquaresGivesOppositeGainsTheRidgeKeepsTheBearingSmall) {
  HiddenScrew h;
  const auto plain = h.Fit(0);
  const auto ridge = h.Fit(FitOptions{}.secondary_key_ridge);
  ASSERT_TRUE(plain.summary.axes[0].thermal_fitted) << plain.summary.FullReport();
  ASSERT_TRUE(ridge.summary.axes[0].thermal_fitted) << ridge.summary.FullReport();
  const auto& kp = plain.model.axes[0].directions[0].GainsFor(CoolantState::kOff)->k_um_per_mm_per_c;
  const auto& kr = ridge.model.axes[0].directions[0].GainsFor(CoolantState::kOff)->k_um_per_mm_per_c;
  ASSERT_EQ(kp.size(), 2u);
  ASSERT_EQ(kr.size(), 2u);
  // Plain: the nut and bearing gains of opposite sign, each larger than the true gain on S.
  EXPECT_LT(kp[0] * kp[1], 0) << kp[0] << " " << kp[1];
  EXPECT_GT(std::abs(kp[1]), std::abs(h.sm.k_nut)) << kp[1];
  // Ridge: the bearing's gain a small part of the nut's, the nut's near the single-key answer.
  EXPECT_LT(std::abs(kr[1]), 0.25 * std::abs(kr[0])) << kr[0] << " " << kr[1];
  EXPECT_NEAR(kr[0], h.sm.k_nut / 1.3, 0.002);  // nut-only: S ≈ nut / (1 + 1.5·0.3)
  // The fit says what it did and what plain least squares would have given.
  EXPECT_THAT(ridge.summary.axes[0].key_selection_reason, HasSubstr("shrunk toward the nut-only fit"));
  EXPECT_THAT(ridge.summary.axes[0].key_selection_reason, HasSubstr("plain least squares"));
  EXPECT_THAT(plain.summary.axes[0].key_selection_reason, ::testing::Not(HasSubstr("shrunk")));
}

TEST(SecondaryKeyRidge, HoldsOnAStateWithABearingHeatTheCalibrationNeverShowed) {
  HiddenScrew h;
  const auto plain = h.Fit(0);
  const auto ridge = h.Fit(FitOptions{}.secondary_key_ridge);
  std::mt19937 rng(99);
  // The same kind of state as the calibration: both fits predict it (plain is exact there).
  const auto seen = h.State("seen-kind", 4.5, 0.3 * 4.5 + 0.02, 0, rng);
  // A state whose bearing carries 1.5 °C the calibration never had (the motor heating it).
  const auto unseen = h.State("unseen-kind", 4.5, 0.3 * 4.5 + 0.02, 1.5, rng);
  const double signal_um = std::abs(h.sm.k_nut) * 4.5 * 500;  // the thermal error at the far end
  EXPECT_LT(HiddenScrew::HeldOutRms(plain, seen), 0.05 * signal_um);
  EXPECT_LT(HiddenScrew::HeldOutRms(ridge, seen), 0.1 * signal_um);
  const double e_plain = HiddenScrew::HeldOutRms(plain, unseen), e_ridge = HiddenScrew::HeldOutRms(ridge, unseen);
  EXPECT_LT(e_ridge, 0.5 * e_plain) << "plain " << e_plain << " µm, ridge " << e_ridge << " µm";
  EXPECT_LT(e_ridge, 0.15 * signal_um) << e_ridge;
}

TEST(SecondaryKeyRidge, OneKeyIsNotShrunkAndZeroIsPlainLeastSquares) {
  SyntheticMachine sm;
  const auto states = sm.MakeStates(sm.DefaultStates());
  FitOptions a, b;
  a.key_sensors = b.key_sensors = {"nut"};
  a.secondary_key_ridge = 0;
  b.secondary_key_ridge = 0.5;  // large: would change any shrunk gain
  const auto ra = FitCompositeModel(states, a), rb = FitCompositeModel(states, b);
  const auto& ka = ra.model.axes[0].directions[0].GainsFor(CoolantState::kOff)->k_um_per_mm_per_c;
  const auto& kb = rb.model.axes[0].directions[0].GainsFor(CoolantState::kOff)->k_um_per_mm_per_c;
  ASSERT_EQ(ka.size(), 1u);
  EXPECT_DOUBLE_EQ(ka[0], kb[0]);
  // With two keys the true gains are recovered by plain least squares (the seed's fit).
  FitOptions c;
  c.key_sensors = {"nut", "bearing"};
  c.secondary_key_ridge = 0;
  const auto rc = FitCompositeModel(states, c);
  const auto& kc = rc.model.axes[0].directions[0].GainsFor(CoolantState::kOff)->k_um_per_mm_per_c;
  EXPECT_NEAR(kc[0], sm.k_nut, 0.0003);
  EXPECT_NEAR(kc[1], sm.k_bearing, 0.0003);
}

TEST(SecondaryKeyRidge, NegativeOrNonFiniteIsInvalid) {
  FitOptions o;
  std::string why;
  o.secondary_key_ridge = -0.1;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_THAT(why, HasSubstr("secondary_key_ridge"));
  o.secondary_key_ridge = std::nan("");
  EXPECT_FALSE(o.IsValid(&why));
  o.secondary_key_ridge = 0;
  EXPECT_TRUE(o.IsValid(&why)) << why;
}

}  // namespace
}  // namespace trueaxis::model
