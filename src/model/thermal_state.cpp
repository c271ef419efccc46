#include "trueaxis/model/thermal_state.hpp"

#include <cmath>

#include "trueaxis/model/thermal_lag.hpp"

namespace trueaxis::model {

double ObserverStep(double state_c, double raw_c, double sink_c, double dt_s, double tau_lag_s, double tau_loss_s) {
  if (!(tau_loss_s > 0) || std::isnan(sink_c)) return LagStep(state_c, raw_c, dt_s, tau_lag_s);
  if (!(tau_lag_s > 0) || std::isnan(raw_c) || std::isnan(state_c) || !(dt_s >= 0)) return raw_c;
  const double a = 1 / tau_lag_s, c = 1 / tau_loss_s;
  const double target = (a * raw_c + c * sink_c) / (a + c);
  return target + (state_c - target) * std::exp(-(a + c) * dt_s);
}

double KeySinkC(const AxisModel& axis, std::size_t k, double ambient_c) {
  const double base = k < axis.baseline_temp_c.size() ? axis.baseline_temp_c[k] : std::nan("");
  if (axis.key_rise_above_ambient && std::isfinite(ambient_c) && std::isfinite(axis.ambient_baseline_c))
    return base + (ambient_c - axis.ambient_baseline_c);
  return base;
}

void AdvanceThermalState(const AxisModel& axis, AxisThermalState& state, const ThermalInputs& in, double dt_s) {
  const std::size_t n = std::min({axis.key_sensors.size(), in.key_c.size(), kMaxStateKeys});
  bool all_read = true;
  for (std::size_t k = 0; k < n; ++k) all_read = all_read && !std::isnan(in.key_c[k]);
  for (std::size_t k = 0; k < n; ++k) {
    const double raw = in.key_c[k];
    state.key_c[k] = !state.valid ? raw
                                  : ObserverStep(state.key_c[k], raw, KeySinkC(axis, k, in.ambient_c), dt_s,
                                                 axis.KeyLagS(k), axis.KeyLossS(k, in.coolant));
  }
  state.valid = all_read;
}

}  // namespace trueaxis::model
