#pragma once
// The warm-up rule of a thermal-model campaign (docs/campaign.md, step 2): while all axes machine,
// the axis is measured each time its nut sensor (1-minute mean) has risen another step above the
// rise of the previous test, and a last time at thermal saturation. One rule, used by the virtual
// machine's campaign (sim::RunCampaign) and by `trueaxis campaign log`, which tells a user on a
// real machine when the next test is due (the campaign module builds on sim, so the rule lives here).
//
//   step = max(nut_step_c, nut_step_growth · |rise at the last test|,
//              (extrapolated saturation rise − rise) / (tests still allowed + 1))
//
// so the tests spread over the whole rise whatever the machine's heat and time constants.
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace trueaxis::sim {

struct WarmUpRule {
  double nut_step_c = 0.5;          // at least this much more rise between two tests …
  double nut_step_growth = 0.25;    // … or this fraction of the rise so far …
  int max_measurements = 16;        // … or the even share of what is still to come over the tests left
                                    //   (the last one is kept for saturation)
  double saturation_window_s = 1800;  // saturated when the nut moved less than
  double saturation_rise_c = 0.15;    //   this much within the window
};

// (warm-up seconds, nut rise °C) since the warm-up started, in time order.
using WarmUpCurve = std::vector<std::pair<double, double>>;

// The rise a first-order warm-up tends to, from its curve so far: the three-point formula
// A = (T0·T2 − T1²)/(T0 + T2 − 2·T1) on equally spaced times (a third, two thirds and all of it).
// NaN while the curve has fewer than 30 points or does not yet bend, or when the extrapolation is
// beyond ten times the present rise.
double EstimateSaturationRise(const WarmUpCurve& curve);

// The |rise| at which the next threshold test is due, after a test at `rise_at_test_c` that was the
// `taken`-th of the warm-up, with the curve up to that test. Before the first test: nut_step_c.
double NextTestRise(const WarmUpRule& rule, const WarmUpCurve& curve, double rise_at_test_c, int taken);

// Whether another threshold test may be taken (one is always kept for saturation).
bool ThresholdTestAllowed(const WarmUpRule& rule, int taken);

// Saturated: `nut_c` holds readings `period_s` apart (the latest last) and spans at least the
// rule's window, over which the nut moved less than saturation_rise_c (settled, up or down).
bool WarmUpSaturated(const WarmUpRule& rule, std::span<const double> nut_c, double period_s);

}  // namespace trueaxis::sim
