#include "trueaxis/sim/warmup_rule.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace trueaxis::sim {

double EstimateSaturationRise(const WarmUpCurve& curve) {
  if (curve.size() < 30) return std::numeric_limits<double>::quiet_NaN();
  const double t_end = curve.back().first;
  auto at = [&](double t) {
    const auto it = std::lower_bound(curve.begin(), curve.end(), t,
                                     [](const std::pair<double, double>& p, double v) { return p.first < v; });
    return it == curve.end() ? curve.back().second : it->second;
  };
  const double t0 = at(t_end / 3), t1 = at(2 * t_end / 3), t2 = curve.back().second;
  const double first = t1 - t0, second = t2 - t1;
  if (!(first > 0.05) || !(second < 0.95 * first)) return std::numeric_limits<double>::quiet_NaN();
  const double den = t0 + t2 - 2 * t1;
  const double a = (t0 * t2 - t1 * t1) / den;
  // Beyond ten times the present rise the extrapolation is not to be trusted.
  return a > t2 && a < 10 * std::max(t2, 0.5) ? a : std::numeric_limits<double>::quiet_NaN();
}

double NextTestRise(const WarmUpRule& rule, const WarmUpCurve& curve, double rise_at_test_c, int taken) {
  if (taken <= 0) return rule.nut_step_c;
  const double rise = rise_at_test_c;
  const double saturation_rise = EstimateSaturationRise(curve);
  const int remaining = rule.max_measurements - 1 - taken;
  // At least nut_step_c, growing with the rise (a hot machine's rise is long; until the curve
  // bends, its end is unknown), and at least the even share of what is still to come.
  double step = std::max(rule.nut_step_c, rule.nut_step_growth * std::abs(rise));
  if (std::isfinite(saturation_rise) && saturation_rise > rise && remaining > 0)
    step = std::max(step, (saturation_rise - rise) / (remaining + 1));
  return std::abs(rise) + step;
}

bool ThresholdTestAllowed(const WarmUpRule& rule, int taken) { return taken + 1 < rule.max_measurements; }

bool WarmUpSaturated(const WarmUpRule& rule, std::span<const double> nut_c, double period_s) {
  if (!(period_s > 0)) return false;
  const auto window = static_cast<std::size_t>(rule.saturation_window_s / period_s);
  if (nut_c.size() <= window) return false;
  const double then = nut_c[nut_c.size() - 1 - window];
  return std::abs(nut_c.back() - then) < rule.saturation_rise_c;
}

}  // namespace trueaxis::sim
