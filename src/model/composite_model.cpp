#include "trueaxis/model/composite_model.hpp"

#include "trueaxis/core/interpolation.hpp"

#include <algorithm>
#include <cmath>

namespace trueaxis::model {

double GeometricError::Evaluate(double position_mm) const {
  if (kind == Kind::kPolynomial) {
    const double u = (position_mm - center_mm) / half_span_mm;
    double acc = 0;
    for (auto it = coefficients_um.rbegin(); it != coefficients_um.rend(); ++it) acc = acc * u + *it;
    return acc;
  }
  return InterpolateClamped(table_position_mm, table_error_um, position_mm);
}

const ThermalGains* DirectionModel::GainsFor(CoolantState coolant) const {
  const ThermalGains* off = nullptr;
  for (const auto& g : thermal) {
    if (g.coolant == coolant) return &g;
    if (g.coolant == CoolantState::kOff) off = &g;
  }
  if (off) return off;
  return thermal.empty() ? nullptr : &thermal.front();
}

const AxisModel* CompositeModel::FindAxis(const std::string& name) const {
  for (const auto& a : axes)
    if (a.axis == name) return &a;
  return nullptr;
}

namespace {

// Key i's rise held at the gains' fitted envelope (the prediction flagged when it is).
inline double HeldRise(const ThermalGains& g, std::size_t i, double rise, Prediction& p) {
  if (i < g.key_rise_range_c.size() && (rise < g.key_rise_range_c[i][0] || rise > g.key_rise_range_c[i][1])) {
    p.tan_beta_limited = true;
    return std::clamp(rise, g.key_rise_range_c[i][0], g.key_rise_range_c[i][1]);
  }
  return rise;
}

}  // namespace

Prediction Predict(const AxisModel& axis, double position_mm, Direction direction, const ThermalState& state) {
  const DirectionModel& dm = axis.For(direction);
  Prediction p;
  double geometric_at_mm = position_mm;
  if (axis.HasMeasuredRange()) {  // beyond the measured range: the end value held, never extrapolated
    geometric_at_mm = std::clamp(position_mm, axis.measured_range_mm[0], axis.measured_range_mm[1]);
    p.position_outside_range = std::abs(position_mm - geometric_at_mm) > kMeasuredRangeToleranceMm;
  }
  p.geometric_um = dm.geometric.Evaluate(geometric_at_mm);
  const double lever_mm = axis.reference_position_mm - position_mm;  // (Px − P0)
  if (state.use_thermal) {
    if (const ThermalGains* g = dm.GainsFor(state.coolant)) {
      double tan_beta = g->offset_um_per_mm;
      const std::size_t n_keys = axis.key_sensors.size();
      const bool motion = axis.HasMotionHeat() && g->k_um_per_mm_per_c.size() > n_keys;
      const std::size_t n_gains = std::min(g->k_um_per_mm_per_c.size(), n_keys);
      bool ok = state.key_temp_c.size() >= n_gains && axis.baseline_temp_c.size() >= n_gains &&
                !(motion && std::isnan(state.motion_m_per_min));
      // Rise above ambient (key_rise_above_ambient): subtract the room's own change.
      double ambient_shift_c = 0;
      if (axis.key_rise_above_ambient && !std::isnan(state.ambient_c) && !std::isnan(axis.ambient_baseline_c))
        ambient_shift_c = state.ambient_c - axis.ambient_baseline_c;
      for (std::size_t i = 0; ok && i < n_gains; ++i) {
        const double t = state.key_temp_c[i];
        if (std::isnan(t)) {
          ok = false;
          continue;
        }
        tan_beta += g->k_um_per_mm_per_c[i] * HeldRise(*g, i, t - axis.baseline_temp_c[i] - ambient_shift_c, p);
      }
      // The motion-heat input: one more key whose rise is M itself (no baseline, no room).
      const double motion_rise = motion && ok ? HeldRise(*g, n_keys, state.motion_m_per_min, p) : 0.0;
      if (motion && ok) tan_beta += g->k_um_per_mm_per_c[n_keys] * motion_rise;
      double shift_um = 0;  // Σ offset_i·ΔT_i (+ the room's): each key's own pivot (none in the seed's form)
      if (ok)
        if (const KeyShifts* ks = axis.ShiftsFor(direction, g)) {
          for (std::size_t i = 0; i < ks->offset_um_per_c.size() && i < n_gains; ++i)
            shift_um += ks->offset_um_per_c[i] *
                        HeldRise(*g, i, state.key_temp_c[i] - axis.baseline_temp_c[i] - ambient_shift_c, p);
          if (motion && ks->offset_um_per_c.size() > n_keys) shift_um += ks->offset_um_per_c[n_keys] * motion_rise;
          if (!std::isnan(state.ambient_c) && !std::isnan(axis.ambient_baseline_c))
            shift_um += ks->ambient_offset_um_per_c * (state.ambient_c - axis.ambient_baseline_c);
        }
      if (!ok) p.tan_beta_limited = false;
      if (ok) {
        if (tan_beta < g->min_tan_beta_um_per_mm || tan_beta > g->max_tan_beta_um_per_mm) {
          tan_beta = std::clamp(tan_beta, g->min_tan_beta_um_per_mm, g->max_tan_beta_um_per_mm);
          p.tan_beta_limited = true;
        }
        p.tan_beta_um_per_mm = tan_beta;
        p.thermal_um = tan_beta * lever_mm + shift_um;
      }
    }
    if (!axis.ambient_sensor.empty() && !std::isnan(state.ambient_c) && !std::isnan(axis.ambient_baseline_c)) {
      p.ambient_um = axis.rho_um_per_mm_per_c * (state.ambient_c - axis.ambient_baseline_c) * lever_mm;
      p.ambient_extrapolated = axis.AmbientOutsideFittedRange(state.ambient_c);
    }
  }
  p.total_um = p.geometric_um + p.thermal_um + p.ambient_um;
  return p;
}

}  // namespace trueaxis::model
