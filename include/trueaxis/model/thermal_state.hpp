#pragma once
// The model-side dynamic state of one axis (issue 10): what Predict() needs that depends on the
// machine's past, not only on the readings of this instant. Today: the effective key temperatures
// that feed tanβ — each key reading passed through its first-order lag (key_lag_s) and, while a
// coolant runs, drawn towards the room by the coolant's loss time constant (key_loss_s): an
// observer of the screw's temperature as its key sensor sees it, with the memory of the coolant
// the nut sensor forgets within minutes (docs/model-file.md "Thermal state").
//
// A state struct and one advance function of (model, state, inputs, dt): pure, allocation-free
// and fixed-size, so the real-time compensator keeps one per axis and calls AdvanceThermalState
// once per cycle, and the fit and `predict --measurement` run the same code along a recording.
#include <array>
#include <cstddef>
#include <limits>
#include <span>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::model {

inline constexpr std::size_t kMaxStateKeys = 16;

struct AxisThermalState {
  std::array<double, kMaxStateKeys> key_c{};  // effective key temperatures, parallel to key_sensors
  bool valid = false;                         // false: the next advance restarts at the readings
  // The motion-heat input M (AxisModel::motion_lag_s): the axis's feed in m/min through its lag.
  // Starts at 0 (the axis at rest for the last few τ) and is not restarted with the keys: it is the
  // axis's own history, which a lost sensor does not change.
  double motion_m_per_min = 0;
  double last_position_mm = std::numeric_limits<double>::quiet_NaN();  // NaN: none yet
};

// The live inputs the model needs (a real CNC supplies them: sensor readings and the coolant state).
struct ThermalInputs {
  std::span<const double> key_c;  // conditioned readings of the key sensors (NaN: lost)
  double ambient_c = std::numeric_limits<double>::quiet_NaN();  // NaN: none (the loss then draws to the baseline)
  CoolantState coolant = CoolantState::kOff;
  // The axis position (mm, the model's frame) for the motion-heat input; NaN: not known this step
  // (a link fault): the step then counts as standstill and the next position starts afresh.
  double position_mm = std::numeric_limits<double>::quiet_NaN();
};

// M towards the feed of this step, |position − last| / dt in m/min, the exact first-order step for a
// feed held over dt: M ← v + (M − v)·exp(−dt/τ). dt <= 0 only records the position.
void AdvanceMotionHeat(double tau_s, AxisThermalState& state, double position_mm, double dt_s);

// One key: towards the reading `raw_c` with τ_lag and, when τ_loss > 0, towards `sink_c` with τ_loss,
// the exact solution for inputs held over dt (so the result does not depend on the cycle time):
//   dT/dt = (raw − T)/τ_lag + (sink − T)/τ_loss
// τ_lag <= 0: no lag (returns raw). τ_loss <= 0: LagStep. State NaN or dt < 0: restart at raw.
double ObserverStep(double state_c, double raw_c, double sink_c, double dt_s, double tau_lag_s, double tau_loss_s);

// Advances `state` by dt_s to the readings `in`. Restarts at the readings when the state is not
// valid or a key reading is NaN (then the state stays invalid until every key reads again).
// Keys beyond kMaxStateKeys are not tracked (the runtime refuses such models).
void AdvanceThermalState(const AxisModel& axis, AxisThermalState& state, const ThermalInputs& in, double dt_s);

// Whether the model has any dynamics at all: a key lag, a coolant loss time constant > 0 or a
// motion-heat input. Without
// them AdvanceThermalState is the identity on the readings (state = readings, valid when every key
// reads), so a real-time caller decides this once per model and skips the advance.
bool HasThermalDynamics(const AxisModel& axis);

// The temperature key k tends to while a coolant draws it to the room: its cold-state baseline,
// moved with the room (above-ambient models) when an ambient reading is given.
double KeySinkC(const AxisModel& axis, std::size_t k, double ambient_c);

}  // namespace trueaxis::model
