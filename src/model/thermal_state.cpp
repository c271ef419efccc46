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

void AdvanceMotionHeat(double tau_s, AxisThermalState& state, double position_mm, double dt_s) {
  if (!(dt_s > 0)) {
    if (!std::isnan(position_mm)) state.last_position_mm = position_mm;
    return;
  }
  const double feed = std::isnan(position_mm) || std::isnan(state.last_position_mm)
                          ? 0.0
                          : std::abs(position_mm - state.last_position_mm) / dt_s * 0.06;  // mm/s → m/min
  state.motion_m_per_min = feed + (state.motion_m_per_min - feed) * std::exp(-dt_s / tau_s);
  state.last_position_mm = position_mm;
}

bool HasThermalDynamics(const AxisModel& axis) {
  if (axis.HasKeyLag() || axis.HasMotionHeat()) return true;
  for (const auto& loss : axis.key_loss_s)
    for (double tau : loss)
      if (tau > 0) return true;
  return false;
}

void AdvanceThermalState(const AxisModel& axis, AxisThermalState& state, const ThermalInputs& in, double dt_s) {
  const std::size_t n = std::min({axis.key_sensors.size(), in.key_c.size(), kMaxStateKeys});
  bool all_read = true;
  for (std::size_t k = 0; k < n; ++k) all_read = all_read && !std::isnan(in.key_c[k]);
  // The coolant's loss constants once per axis; without a loss the step is the plain lag (inline,
  // no sink to compute): the real-time path pays for the observer only while a coolant runs.
  const std::vector<double>& loss = axis.key_loss_s[static_cast<std::size_t>(in.coolant) % axis.key_loss_s.size()];
  for (std::size_t k = 0; k < n; ++k) {
    const double raw = in.key_c[k];
    const double tau_loss = k < loss.size() ? loss[k] : 0.0;
    if (!state.valid) state.key_c[k] = raw;
    else if (!(tau_loss > 0)) state.key_c[k] = LagStep(state.key_c[k], raw, dt_s, axis.KeyLagS(k, state.key_c[k], raw));
    else state.key_c[k] = ObserverStep(state.key_c[k], raw, KeySinkC(axis, k, in.ambient_c), dt_s, axis.KeyLagS(k), tau_loss);
  }
  state.valid = all_read;
  if (axis.HasMotionHeat()) AdvanceMotionHeat(axis.motion_lag_s, state, in.position_mm, dt_s);
}

}  // namespace trueaxis::model
