#pragma once
// First-order thermal lag of a key-sensor temperature (docs/model-file.md "Thermal lag").
//
// A sensor on the nut follows the heat source quickly, the screw whose length
// makes the error follows it with a delay. The model may therefore feed tanβ
// with the sensor's reading passed through a first-order lag of time constant
// τ (the exact discretisation of dT_eff/dt = (T − T_eff)/τ for T held over Δt):
//
//   T_eff ← T_eff + (T − T_eff)·(1 − exp(−Δt/τ))
//
// τ = 0 (the default) means no lag: T_eff = T, exactly today's static model.
// Pure and allocation-free: the runtime compensator calls it every cycle.
#include <cmath>

namespace trueaxis::model {

// One step. Returns the new lagged value.
//  - tau_s <= 0 (or NaN): no lag, returns raw_c.
//  - lagged_c NaN (no state yet) or dt_s < 0 (time went backwards): restart at raw_c.
//  - raw_c NaN: NaN (the caller resets its state; Predict treats NaN as "no thermal part").
inline double LagStep(double lagged_c, double raw_c, double dt_s, double tau_s) {
  if (!(tau_s > 0) || std::isnan(raw_c) || std::isnan(lagged_c) || !(dt_s >= 0)) return raw_c;
  const double alpha = -std::expm1(-dt_s / tau_s);  // 1 − exp(−Δt/τ), accurate for small Δt/τ
  return lagged_c + (raw_c - lagged_c) * alpha;
}

}  // namespace trueaxis::model
