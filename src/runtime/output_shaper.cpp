#include "trueaxis/runtime/output_shaper.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace trueaxis::runtime {

bool OutputShaperOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string m) {
    if (why) *why = std::move(m);
    return false;
  };
  if (!(max_correction_um >= 0) || !std::isfinite(max_correction_um))
    return fail(fmt::format("max_correction_um must be >= 0, got {}", max_correction_um));
  if (!(max_step_um > 0) || !std::isfinite(max_step_um))
    return fail(fmt::format("max_step_um must be > 0, got {}", max_step_um));
  if (!(hysteresis >= 0 && hysteresis <= 0.5))
    return fail(fmt::format("hysteresis must be in [0, 0.5] quanta, got {}", hysteresis));
  return true;
}

ShaperLimits ShaperLimits::For(const OutputShaperOptions& o, double quantum_um) {
  ShaperLimits l;
  l.options = o;
  l.quantum_um = quantum_um;
  // (both quotients are >= 0, so truncation is the floor)
  l.max_counts_step = std::max<std::int64_t>(1, static_cast<std::int64_t>(o.max_step_um / quantum_um + 1e-9));
  l.bound_counts = static_cast<std::int64_t>(o.max_correction_um / quantum_um + 1e-9);
  return l;
}

OutputShaperState ShapeOutput(const OutputShaperState& state, double desired_um, double quantum_um,
                              const OutputShaperOptions& o) {
  return ShapeOutput(state, desired_um, ShaperLimits::For(o, quantum_um));
}

OutputShaperState ShapeOutput(const OutputShaperState& state, double desired_um, const ShaperLimits& limits) {
  const OutputShaperOptions& o = limits.options;
  const double quantum_um = limits.quantum_um;
  OutputShaperState next = state;
  if (std::isnan(desired_um)) return next;  // hold
  // 1. bound (also maps ±inf to the bound)
  const double bounded = std::clamp(desired_um, -o.max_correction_um, o.max_correction_um);
  // 2. rate limit the unquantised value
  next.ramp_um = state.ramp_um + std::clamp(bounded - state.ramp_um, -o.max_step_um, o.max_step_um);
  // 3. quantise with hysteresis: keep the count while within ±(0.5 + h) quanta
  const double in_counts = next.ramp_um / quantum_um;
  std::int64_t target = state.counts;
  if (std::fabs(in_counts - static_cast<double>(state.counts)) > 0.5 + o.hysteresis)
    target = static_cast<std::int64_t>(std::llround(in_counts));
  // 4. never more than the step (at least one count) per cycle, never beyond the bound
  target = std::clamp(target, state.counts - limits.max_counts_step, state.counts + limits.max_counts_step);
  target = std::clamp(target, -limits.bound_counts, limits.bound_counts);
  next.counts = target;
  return next;
}

}  // namespace trueaxis::runtime
