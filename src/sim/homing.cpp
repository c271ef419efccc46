#include "trueaxis/sim/homing.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::sim {

std::optional<HomingMethod> ParseHomingMethod(std::string_view text) {
  if (text == "switch") return HomingMethod::kSwitchOnly;
  if (text == "switch+index" || text == "index") return HomingMethod::kSwitchAndIndex;
  return std::nullopt;
}

std::string_view HomingMethodName(HomingMethod m) {
  return m == HomingMethod::kSwitchOnly ? "switch" : "switch+index";
}

HomingResult HomeAxis(VirtualMachine& vm, std::size_t axis, HomingMethod method, std::mt19937_64& rng) {
  const AxisDescription& d = vm.description().axes.at(axis);
  const double ref = d.reference_mm;
  const double to_index_mm = std::isnan(d.home_switch_to_index_mm) ? d.lead_mm / 2 : d.home_switch_to_index_mm;
  constexpr double kFastFeed = 3000, kSearchFeed = 500, kBackOffMm = 2;
  // Start the search beyond the switch on the + side, search in − onto the reference.
  vm.MoveTo(axis, std::min(d.travel_mm, ref + to_index_mm + kBackOffMm), kFastFeed);
  vm.MoveTo(axis, ref, kSearchFeed);
  std::normal_distribution<double> nd(0, 1);
  HomingResult r;
  r.method = method;
  r.switch_error_um = nd(rng) * d.home_switch_scatter_um;
  const double index_jitter_um = nd(rng) * d.homing_repeatability_um;
  if (method == HomingMethod::kSwitchOnly) {
    r.offset_um = r.switch_error_um;
  } else {
    // Searching in −: the trip lies to_index + e before the mark at the reference;
    // below zero it tripped past that mark and the next one (a lead lower) is taken.
    const double trip_to_mark_mm = to_index_mm + r.switch_error_um * 1e-3;
    r.index_marks_skipped = static_cast<int>(std::floor(trip_to_mark_mm / d.lead_mm));
    r.offset_um = r.index_marks_skipped * d.lead_mm * 1000.0 + index_jitter_um;
  }
  // Back off and approach the reference forward (the play on the + flank, as the laser's zero).
  vm.MoveTo(axis, std::max(0.0, ref - kBackOffMm), kFastFeed);
  vm.MoveTo(axis, ref, kSearchFeed);
  vm.SetHomingOffsetUm(axis, r.offset_um);
  return r;
}

}  // namespace trueaxis::sim
