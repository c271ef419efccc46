#pragma once
// OutputShaper: turns the correction the model asks for into what may be
// written to the CNC this cycle (MISSION M6 "never hurt the machine").
//
//   desired ─► bound (|c| ≤ max_correction_um)
//           ─► rate limit (|Δ| ≤ max_step_um per cycle, on the UNQUANTISED value)
//           ─► quantise to the physical quantum q with hysteresis
//           ─► clamp the count change to max(1, ⌊max_step/q⌋) counts per cycle
//
// Guarantees, for every cycle, whatever `desired` does (jumps, NaN, ±inf):
//   |output| ≤ max_correction_um (rounded down to q),
//   |Δoutput| ≤ max(q, max_step_um),
//   output = counts·q exactly.
// Quantising the rate-limited value (not the raw one) and holding the count
// until the value leaves a band of ±(0.5 + hysteresis)·q around it means a
// value sitting on a rounding boundary, or noise of less than ±hysteresis·q
// about it, never makes the output toggle (no limit cycling).
//
// Pure value type: no allocation; the state is two numbers.
#include <cmath>
#include <cstdint>
#include <string>

namespace trueaxis::runtime {

struct OutputShaperOptions {
  double max_correction_um = 100;  // bound on |correction| (physical µm)
  double max_step_um = 1.0;        // bound on the change per cycle (physical µm)
  double hysteresis = 0.25;        // quantiser hysteresis, in quanta (0 .. 0.5)

  bool IsValid(std::string* why) const;
};

struct OutputShaperState {
  double ramp_um = 0;     // rate-limited value before quantisation
  std::int64_t counts = 0;  // output = counts · quantum
};

// One axis's shaping constants, computed once (the real-time step keeps one per axis): the
// options, the quantum and the two count limits that would otherwise cost two divisions a cycle.
struct ShaperLimits {
  OutputShaperOptions options;
  double quantum_um = 1.0;
  std::int64_t max_counts_step = 1;  // max(1, ⌊max_step_um / q⌋)
  std::int64_t bound_counts = 0;     // ⌊max_correction_um / q⌋
  static ShaperLimits For(const OutputShaperOptions& options, double quantum_um);
};

// One cycle. `desired_um` NaN is treated as "hold" (no change).
OutputShaperState ShapeOutput(const OutputShaperState& state, double desired_um, const ShaperLimits& limits);
OutputShaperState ShapeOutput(const OutputShaperState& state, double desired_um, double quantum_um,
                              const OutputShaperOptions& options);

// The shaper picked up at what the CNC applies now (physical µm): the ramp continues from there.
inline OutputShaperState PickUpAt(double applied_physical_um, double quantum_um) {
  return {applied_physical_um, std::llround(applied_physical_um / quantum_um)};
}

inline double OutputUm(const OutputShaperState& s, double quantum_um) {
  return static_cast<double>(s.counts) * quantum_um;
}

}  // namespace trueaxis::runtime
