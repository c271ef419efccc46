// The plan's ISO 230-2 target lists: inside the soft limits with the overrun, enough targets, a
// random component that samples the lead at many phases, the same list for the same seed.
#include "trueaxis/campaign/test_targets.hpp"

#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "trueaxis/campaign/campaign_machine.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::campaign {
namespace {

const std::string kSource = TRUEAXIS_SOURCE_DIR;

CampaignAxis Axis(double min_mm, double max_mm, double lead_mm) {
  CampaignAxis a;
  a.name = "X";
  a.min_mm = min_mm;
  a.max_mm = max_mm;
  a.lead_mm = lead_mm;
  return a;
}

TEST(TestTargets, EveryExampleAxisFollowsIso230_2) {
  for (const std::string file : {"/examples/campaign/vmc850_fanuc.toml", "/examples/machines/vmc850.toml",
                                 "/examples/machines/gantry2000.toml", "/examples/machines/lathe_tc620.toml"}) {
    const auto m = ReadCampaignMachineFile(kSource + file);
    for (const auto& a : m.axes) {
      const TargetOptions o;
      const auto t = PlanAxisTargets(a, o);
      SCOPED_TRACE(file + " axis " + a.name);
      EXPECT_TRUE(TargetProblems(a, t).empty());
      // Within the soft limits with the overrun and the clearance beyond each end.
      EXPECT_GE(t.targets_mm.front() - o.overrun_mm, a.min_mm + o.end_clearance_mm - 1e-9);
      EXPECT_LE(t.targets_mm.back() + o.overrun_mm, a.max_mm - o.end_clearance_mm + 1e-9);
      // At least five per metre, at least five in all; about one per spacing.
      const double measured = t.targets_mm.back() - t.targets_mm.front();
      EXPECT_GE(t.targets_mm.size(), std::max<std::size_t>(5, static_cast<std::size_t>(std::ceil(measured / 200))));
      EXPECT_NEAR(static_cast<double>(t.targets_mm.size() - 1), std::max(4.0, std::round(measured / o.spacing_mm)), 0.5);
      for (std::size_t i = 1; i < t.targets_mm.size(); ++i) EXPECT_GT(t.targets_mm[i], t.targets_mm[i - 1]);
      for (double x : t.targets_mm) EXPECT_NEAR(x * 1000, std::round(x * 1000), 1e-6);  // 1 µm grid
    }
  }
}

TEST(TestTargets, RandomComponentSamplesTheLeadAtManyPhases) {
  const auto a = Axis(-850, 0, 12);
  TargetOptions o;
  const auto t = PlanAxisTargets(a, o);
  ASSERT_EQ(t.targets_mm.size(), 35u);  // 838 mm at ~25 mm
  EXPECT_DOUBLE_EQ(t.random_max_mm, 6);  // min(lead/2, p/4)
  int off_grid = 0;
  std::set<int> phases;  // the lead in 6 bins
  for (std::size_t i = 0; i < t.targets_mm.size(); ++i) {
    const double even = t.targets_mm.front() + static_cast<double>(i) * t.spacing_mm;
    const double r = t.targets_mm[i] - even;
    EXPECT_LE(std::abs(r), t.random_max_mm + 1e-3);
    off_grid += std::abs(r) > 0.5;
    const double phase = std::fmod(t.targets_mm[i] - a.min_mm, a.lead_mm) / a.lead_mm;
    phases.insert(static_cast<int>(phase * 6));
  }
  EXPECT_GT(off_grid, 20);
  EXPECT_EQ(phases.size(), 6u);
  // The ends stay at the ends of the measurement travel.
  EXPECT_DOUBLE_EQ(t.targets_mm.front(), -844);
  EXPECT_DOUBLE_EQ(t.targets_mm.back(), -6);

  // Evenly spaced on request: a spacing of 24.647 mm on a 12 mm lead samples few phases per metre.
  o.random_component = false;
  const auto even = PlanAxisTargets(a, o);
  EXPECT_EQ(even.random_max_mm, 0);
  for (std::size_t i = 0; i < even.targets_mm.size(); ++i)
    EXPECT_NEAR(even.targets_mm[i], even.targets_mm.front() + static_cast<double>(i) * even.spacing_mm, 0.0006);
}

TEST(TestTargets, SameSeedSameListOtherSeedOther) {
  const auto a = Axis(0, 500, 10);
  TargetOptions o;
  const auto t1 = PlanAxisTargets(a, o), t2 = PlanAxisTargets(a, o);
  EXPECT_EQ(t1.targets_mm, t2.targets_mm);
  o.seed = 2;
  EXPECT_NE(PlanAxisTargets(a, o).targets_mm, t1.targets_mm);
}

TEST(TestTargets, FiveTargetsAtLeastAndTooShortRefused) {
  TargetOptions o;
  o.spacing_mm = 500;
  const auto a = Axis(0, 850, 12);
  EXPECT_EQ(PlanAxisTargets(a, o).targets_mm.size(), 5u);  // 838 mm: 5 per metre → 5
  const auto long_axis = Axis(0, 2000, 20);
  EXPECT_EQ(PlanAxisTargets(long_axis, o).targets_mm.size(), 10u);  // 1988 mm: ceil(9.94)
  o.spacing_mm = 25;
  EXPECT_THROW(PlanAxisTargets(Axis(0, 14, 5), o), InputError);  // 2 mm left between the overruns
  o.runs = 0;
  EXPECT_THROW(PlanAxisTargets(a, o), InputError);
}

TEST(TestTargets, ProblemsAreFound) {
  const auto a = Axis(0, 500, 10);
  auto t = PlanAxisTargets(a, TargetOptions{});
  t.targets_mm.front() = 2;  // its overrun would reach −3 mm
  t.targets_mm[3] = t.targets_mm[2];
  const auto problems = TargetProblems(a, t);
  ASSERT_GE(problems.size(), 2u);
  EXPECT_NE(problems[0].find("beyond the limit 0 mm"), std::string::npos) << problems[0];
  EXPECT_NE(problems[1].find("not ascending"), std::string::npos) << problems[1];
  t = PlanAxisTargets(a, TargetOptions{});
  t.targets_mm.resize(3);
  EXPECT_FALSE(TargetProblems(a, t).empty());
}

TEST(TestTargets, DurationCountsMovesAndDwells) {
  AxisTargets t;
  t.targets_mm = {0, 100, 200};
  t.overrun_mm = 5;
  t.dwell_s = 3;
  t.feed_mm_min = 2100;
  // Per run: 2 × 210 mm at 35 mm/s = 12 s, 6 dwells = 18 s.
  EXPECT_DOUBLE_EQ(TestDurationS(t, 5), 5 * 30.0);
}

}  // namespace
}  // namespace trueaxis::campaign
