#include "trueaxis/runtime/axis_interface.hpp"

#include <fmt/format.h>

namespace trueaxis::runtime {

bool AxisInterface::IsValid(std::string* why) const {
  auto fail = [&](std::string m) {
    if (why) *why = fmt::format("axis '{}': {}", axis, m);
    return false;
  };
  if (axis.empty()) return fail("axis name is empty");
  if (!(pulse_equivalent_um > 0) || !std::isfinite(pulse_equivalent_um))
    return fail(fmt::format("pulse_equivalent_um must be > 0, got {}", pulse_equivalent_um));
  if (!std::isfinite(position_offset_mm)) return fail("position_offset_mm must be finite");
  if (std::isinf(reference_position_mm)) return fail("reference_position_mm must be finite (or unset)");
  if (!std::isnan(max_correction_um) && !(max_correction_um > 0 && max_correction_um <= 10000))
    return fail(fmt::format("max_correction_um must be in (0, 10000] µm, got {}", max_correction_um));
  return true;
}

}  // namespace trueaxis::runtime
