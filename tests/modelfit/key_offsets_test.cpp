// Each key's own pivot (FitOptions::key_offsets, AxisModel::key_shifts; issue 10): a key's
// rise shifts the error over the whole travel as well as tilting it about Px.
#include <cmath>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "synthetic_machine.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::model {
namespace {

using testing::SyntheticMachine;
using ::testing::HasSubstr;

AxisModel OneKeyAxis() {
  AxisModel a = testing::OneKeyAxis(-0.01);
  a.reference_position_mm = 10;
  for (auto& shifts : a.key_shifts) shifts.push_back({{1.5}, -0.5});
  return a;
}

TEST(KeyOffsets, PredictAddsEachKeysShiftToItsSlopeAboutPx) {
  const AxisModel a = OneKeyAxis();
  const std::vector<double> nut{24};  // rise 4 °C (the room at its baseline)
  ThermalState st;
  st.key_temp_c = nut;
  st.ambient_c = 20;
  for (double x : {0.0, 10.0, 250.0}) {
    const auto p = Predict(a, x, Direction::kForward, st);
    EXPECT_NEAR(p.thermal_um, -0.01 * 4 * (10 - x) + 1.5 * 4, 1e-9) << x;
  }
  // At Px only the shift is left: the key pivots at Px + offset/k = 10 − 150 mm.
  EXPECT_NEAR(Predict(a, -140, Direction::kForward, st).thermal_um, 0, 1e-9);
  // The room's change shifts too (key rise measured above the room when the model says so).
  st.ambient_c = 22;
  const auto p = Predict(a, 10, Direction::kForward, st);
  EXPECT_NEAR(p.thermal_um, 1.5 * 4 - 0.5 * 2, 1e-9);
}

// The synthetic machine with a shift per key rise on top of the fan about Px.
std::vector<FitState> ShiftedStates(const SyntheticMachine& sm, double shift_nut, double shift_bearing) {
  std::mt19937 rng(sm.seed);
  std::vector<FitState> out;
  for (const auto& s : sm.DefaultStates()) {
    auto m = sm.Make(s, rng);
    for (auto& p : m.points) p.deviation_um += shift_nut * s.nut_rise + shift_bearing * s.bearing_rise;
    out.push_back(MakeFitState(m));
  }
  return out;
}

TEST(KeyOffsets, FitRecoversTheShiftsAndKeepsThemByCrossValidation) {
  SyntheticMachine sm;
  FitOptions o;
  o.key_sensors = {"nut", "bearing"};
  o.secondary_key_ridge = 0;     // the truth is exactly this form
  o.reference_position_mm = 0;   // the screw's fixed end, as given by a user who knows it
  const auto res = FitCompositeModel(ShiftedStates(sm, 1.2, -0.8), o);
  const auto& s = res.summary.axes[0];
  ASSERT_TRUE(s.thermal_fitted) << res.summary.FullReport();
  EXPECT_TRUE(s.key_offsets) << s.key_offsets_reason;
  EXPECT_THAT(s.key_offsets_reason, HasSubstr("each key's own pivot"));
  for (int d = 0; d < 2; ++d) {
    const auto& ax = res.model.axes[0];
    const auto* g = ax.directions[d].GainsFor(CoolantState::kOff);
    const auto* ks = ax.ShiftsFor(d == 0 ? Direction::kForward : Direction::kReverse, g);
    ASSERT_NE(ks, nullptr);
    ASSERT_EQ(ks->offset_um_per_c.size(), 2u);
    EXPECT_NEAR(ks->offset_um_per_c[0], 1.2, 0.1) << d;
    EXPECT_NEAR(ks->offset_um_per_c[1], -0.8, 0.1) << d;
    EXPECT_NEAR(g->k_um_per_mm_per_c[0], sm.k_nut, 0.0006) << d;
    EXPECT_NEAR(g->k_um_per_mm_per_c[1], sm.k_bearing, 0.0006) << d;
  }
  for (const auto& st : s.states) EXPECT_LT(st.residual_rms_um, 0.3) << st.label;
  // The same data with one pivot only: what the shifts cost the seed's form.
  o.key_offsets = FitOptions::KeyOffsets::kOff;
  const auto one = FitCompositeModel(ShiftedStates(sm, 1.2, -0.8), o);
  EXPECT_FALSE(one.summary.axes[0].key_offsets);
  EXPECT_TRUE(one.model.axes[0].key_shifts[0].empty());
  EXPECT_GT(one.summary.axes[0].thermal_cv_rms_um, 3 * s.thermal_cv_rms_um);
}

TEST(KeyOffsets, AFanAboutOnePivotKeepsTheSeedsForm) {
  SyntheticMachine sm;  // no shift: the seed's fan is the truth
  FitOptions o;
  o.key_sensors = {"nut", "bearing"};
  const auto res = FitCompositeModel(sm.MakeStates(sm.DefaultStates()), o);
  const auto& s = res.summary.axes[0];
  EXPECT_FALSE(s.key_offsets) << s.key_offsets_reason;
  EXPECT_THAT(s.key_offsets_reason, HasSubstr("one pivot Px"));
  EXPECT_TRUE(res.model.axes[0].key_shifts[0].empty());
}

TEST(KeyOffsets, ModelFileKeepsTheShiftsAndOlderFilesReadWithout) {
  CompositeModel m;
  m.axes.push_back(OneKeyAxis());
  const std::string text = ModelToJson(m).dump();
  const auto back = ModelFromJson(nlohmann::json::parse(text), "mem.json");
  const auto* ks = back.axes[0].ShiftsFor(Direction::kReverse, back.axes[0].directions[1].GainsFor(CoolantState::kOff));
  ASSERT_NE(ks, nullptr);
  ASSERT_EQ(ks->offset_um_per_c.size(), 1u);
  EXPECT_DOUBLE_EQ(ks->offset_um_per_c[0], 1.5);
  EXPECT_DOUBLE_EQ(ks->ambient_offset_um_per_c, -0.5);
  // Without the fields (a file written before them): no shift.
  auto plain = m;
  for (auto& v : plain.axes[0].key_shifts) v.clear();
  const std::string old_text = ModelToJson(plain).dump();
  EXPECT_THAT(old_text, ::testing::Not(HasSubstr("offset_um_per_c")));
  EXPECT_TRUE(ModelFromJson(nlohmann::json::parse(old_text), "old.json").axes[0].key_shifts[0].empty());
  // A count that does not match the keys names the field.
  std::string bad = text;
  const auto at = bad.find("\"offset_um_per_c\"");
  ASSERT_NE(at, std::string::npos);
  const auto open = bad.find('[', at), close = bad.find(']', at);
  bad.replace(open, close - open + 1, "[1.5, 2.0]");
  try {
    ModelFromJson(nlohmann::json::parse(bad), "bad.json");
    FAIL() << "accepted two offsets for one key";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("offset_um_per_c"));
  }
}

TEST(KeyOffsets, OptionsAcceptTheThreeForms) {
  FitOptions o;
  std::string why;
  for (auto k : {FitOptions::KeyOffsets::kAuto, FitOptions::KeyOffsets::kOn, FitOptions::KeyOffsets::kOff}) {
    o.key_offsets = k;
    EXPECT_TRUE(o.IsValid(&why)) << why;
  }
}

}  // namespace
}  // namespace trueaxis::model
