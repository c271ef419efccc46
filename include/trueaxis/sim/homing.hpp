#pragma once
// Homing of one axis of the virtual machine by its home switch, with or
// without the motor encoder's index pulse (seed 002 §2.1).
//
// The switch's trip point scatters (mechanical switch, σ = home_switch_scatter_um,
// seed 002 measured a spread of [−0.1, +0.01] mm when the table stopped on
// the switch). The motor encoder's index pulse is sharp (σ = homing_repeatability_um)
// and comes once per motor revolution, i.e. once per lead on a direct-coupled
// screw. Homing:
//   switch only:      the position captured at the switch's trip is the reference
//                     → reference error = the switch's scatter.
//   switch + index:   the switch arms the search; the first index pulse after the
//                     trip is the reference → reference error = the index's jitter,
//                     as long as the switch trips on the same side of that index
//                     mark every time. The trip is nominally home_switch_to_index_mm
//                     (default half a lead) before the mark; a trip scattered past
//                     the mark picks the next one, a whole lead off — reported,
//                     never hidden (HomingResult::index_marks_skipped).
// The search runs in − direction onto the reference; the axis then backs off
// and approaches the reference forward, as VirtualMachine::Home does.
#include <cstddef>
#include <optional>
#include <random>
#include <string_view>

#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {

enum class HomingMethod { kSwitchOnly, kSwitchAndIndex };

std::optional<HomingMethod> ParseHomingMethod(std::string_view text);  // "switch", "switch+index" / "index"
std::string_view HomingMethodName(HomingMethod m);

struct HomingResult {
  HomingMethod method = HomingMethod::kSwitchAndIndex;
  double switch_error_um = 0;   // where the switch tripped, relative to its nominal point
  int index_marks_skipped = 0;  // switch + index: 0 normally, ±1 when the trip crossed the mark
  double offset_um = 0;         // reference error now applied to the axis (VirtualMachine::HomingOffsetUm)
};

// Homes `axis` of `vm` (moves it, takes machine time) and sets its reference error.
HomingResult HomeAxis(VirtualMachine& vm, std::size_t axis, HomingMethod method, std::mt19937_64& rng);

}  // namespace trueaxis::sim
