// The compensator feeds a model's motion-heat input (AxisModel::motion_lag_s, modelfit/motion_heat.hpp)
// from the CNC's positions, cycle by cycle: the axis's feed through the model's lag, into tanβ.
#include <cmath>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/model/thermal_state.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime {
namespace {
using testing::TestAxisModel;

constexpr double kMotionGain = -0.003;  // µm/mm per m/min

std::shared_ptr<const model::CompositeModel> MotionModel(double tau_s) {
  auto m = std::make_shared<model::CompositeModel>();
  m->axes.push_back(TestAxisModel("X"));
  m->axes.back().motion_lag_s = tau_s;
  for (auto& d : m->axes.back().directions)
    for (auto& g : d.thermal) g.k_um_per_mm_per_c.push_back(kMotionGain);
  return m;
}

// The correction the model asks for at `x_mm` with the keys at 20 °C (no rise) and M.
double Expected(const model::CompositeModel& m, double x_mm, double motion_m_per_min,
                Direction dir = Direction::kForward) {
  const double key[2] = {20, 20};
  const model::ThermalState ts{std::span<const double>(key, 2), 20.0, CoolantState::kOff, true, motion_m_per_min};
  return model::CorrectionUm(model::Predict(m.axes[0], x_mm, dir, ts));
}

TEST(CompensatorMotionHeat, TheAxisFeedThroughTheLagEntersTheCorrection) {
  testing::OneAxisRig r;
  const auto m = MotionModel(600);
  r.comp->PublishModel(m, "motion");
  // 2 m/min (33.3 mm/s) back and forth between 100 and 900 mm in 10 ms cycles for 20 min.
  double x = 100, dir = 1, t = 0;
  model::AxisThermalState reference;
  model::AdvanceMotionHeat(600, reference, x, 0);
  r.cnc.axes[0] = {x, +1, true};
  r.comp->RunCycle(r.cnc, r.temps, t);
  const CycleStatus* s = nullptr;
  for (int i = 0; i < 120000; ++i) {
    x += dir * 33.333333333333336 * 0.01;
    if (x > 900 || x < 100) dir = -dir, x = std::clamp(x, 100.0, 900.0);
    t += 0.01;
    r.cnc.axes[0] = {x, dir > 0 ? +1 : -1, true};
    model::AdvanceMotionHeat(600, reference, x, 0.01);
    s = &r.comp->RunCycle(r.cnc, r.temps, t);
  }
  EXPECT_NEAR(reference.motion_m_per_min, 2 * (1 - std::exp(-2.0)), 0.01);
  EXPECT_NEAR(s->axes[0].desired_um, Expected(*m, x, reference.motion_m_per_min, s->axes[0].direction), 1e-6);
  // The motion part is really there: without it the correction differs by k·M·(Px − x).
  EXPECT_GT(std::fabs(Expected(*m, 500, reference.motion_m_per_min) - Expected(*m, 500, 0)), 1.0);
  // The axis stops: M decays with τ; the correction follows it down.
  r.cnc.axes[0] = {500, +1, false};
  const double at_stop = reference.motion_m_per_min;
  s = &r.comp->RunCycle(r.cnc, r.temps, t += 0.01);
  s = &r.comp->RunCycle(r.cnc, r.temps, t += 600);
  const double feed_of_jump = std::fabs(500 - x) / 0.01 * 0.06;  // the jump to 500 mm in one cycle
  const double m_then = feed_of_jump + (at_stop - feed_of_jump) * std::exp(-0.01 / 600);
  EXPECT_NEAR(s->axes[0].desired_um, Expected(*m, 500, m_then * std::exp(-1.0)), 1e-6);
}

TEST(CompensatorMotionHeat, ALinkFaultCountsAsStandstillNotAsAJump) {
  testing::OneAxisRig r;
  const auto m = MotionModel(600);
  r.comp->PublishModel(m, "motion");
  r.cnc.axes[0] = {100, +1, true};
  r.comp->RunCycle(r.cnc, r.temps, 0);
  r.cnc.SetReadOk(false);
  for (int i = 1; i <= 10; ++i) r.comp->RunCycle(r.cnc, r.temps, i * 0.01);
  r.cnc.SetReadOk(true);
  r.cnc.axes[0] = {900, +1, true};  // moved 800 mm while the link was down
  double t = 0.1;
  const CycleStatus* s = nullptr;
  for (int i = 0; i < 50; ++i) s = &r.comp->RunCycle(r.cnc, r.temps, t += 0.01);  // the link recovers
  ASSERT_TRUE(s->axes[0].enabled);
  // M stays at rest: the 800 mm were not counted as one cycle's feed (that would be 4800 m/min).
  EXPECT_NEAR(s->axes[0].desired_um, Expected(*m, 900, 0), 1e-6);
}

}  // namespace
}  // namespace trueaxis::runtime
