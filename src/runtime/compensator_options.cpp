#include "trueaxis/runtime/compensator_options.hpp"

#include <cmath>

#include <fmt/format.h>

namespace trueaxis::runtime {

signal::FaultOptions DefaultJudgeLimits() {
  signal::FaultOptions f;
  f.min_plausible_c = -20;
  f.max_plausible_c = 120;
  f.max_rate_c_per_s = 2.0;
  f.rate_allowance_c = 0.5;
  return f;
}

bool SensorFaultPolicy::IsValid(std::string* why) const {
  auto fail = [&](std::string m) {
    if (why) *why = std::move(m);
    return false;
  };
  std::string inner;
  if (!judge.IsValid(&inner)) return fail("sensor judge: " + inner);
  if (!(hold_last_good_s >= 0) || !std::isfinite(hold_last_good_s)) return fail("hold_last_good_s must be >= 0");
  if (!(fallback_handover_s >= 0) || !std::isfinite(fallback_handover_s))
    return fail("fallback_handover_s must be >= 0 (0: no hand-over)");
  if (!(stale_after_s > 0) || !std::isfinite(stale_after_s)) return fail("stale_after_s must be > 0");
  return true;
}

bool CompensatorOptions::IsValid(std::string* why) const {
  if (!shaper.IsValid(why)) return false;
  if (!sensor.IsValid(why)) return false;
  if (link_recovery_cycles < 1) {
    if (why) *why = "link_recovery_cycles must be >= 1";
    return false;
  }
  if (!(link_stale_after_s > 0) || !std::isfinite(link_stale_after_s)) {
    if (why) *why = "link_stale_after_s must be > 0";
    return false;
  }
  if (!(direction_min_move_um > 0) || !std::isfinite(direction_min_move_um)) {
    if (why) *why = "direction_min_move_um must be > 0";
    return false;
  }
  return true;
}

}  // namespace trueaxis::runtime
