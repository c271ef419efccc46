#include "trueaxis/model/compensation_bound.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace trueaxis::model {

bool CompensationBoundOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (!(extra_rise_c >= 0 && extra_rise_c <= 50)) return fail("extra_rise_c must be in 0..50 °C");
  if (!(ambient_margin_c >= 0 && ambient_margin_c <= 30)) return fail("ambient_margin_c must be in 0..30 °C");
  if (!(margin_fraction >= 0 && margin_fraction <= 5)) return fail("margin_fraction must be in 0..5");
  if (!(round_to_um > 0 && round_to_um <= 100)) return fail("round_to_um must be in (0, 100] µm");
  if (!(min_bound_um > 0)) return fail("min_bound_um must be > 0");
  if (!(controller_limit_um >= min_bound_um)) return fail("controller_limit_um must be >= min_bound_um");
  return true;
}

std::string CompensationBound::BriefReport() const {
  return fmt::format("±{:g} µm (the model asks for up to {:.1f} µm over travel and temperatures{})", bound_um,
                     model_max_um, limited_by_controller ? "; LIMITED by the controller: it will saturate" : "");
}

namespace {

std::vector<double> Positions(const GeometricError& g) {
  if (g.kind == GeometricError::Kind::kTable) return g.table_position_mm;
  std::vector<double> x;
  for (int i = 0; i <= 200; ++i) x.push_back(g.center_mm - g.half_span_mm + g.half_span_mm * i / 100.0);
  return x;
}

// The largest |correction| of one model (the axis's own or a fallback) over the envelope.
double LargestCorrection(const AxisModel& axis, const CompensationBoundOptions& o) {
  const std::size_t keys = axis.key_sensors.size();
  // Two levels per key sensor: the coolest and the hottest it may be.
  std::vector<std::array<double, 2>> levels(keys);
  for (std::size_t k = 0; k < keys; ++k) {
    const double base = k < axis.baseline_temp_c.size() ? axis.baseline_temp_c[k] : 20.0;
    if (k < axis.key_fitted_range_c.size())
      levels[k] = {axis.key_fitted_range_c[k][0], axis.key_fitted_range_c[k][1] + o.extra_rise_c};
    else
      levels[k] = {base, base + 15 + o.extra_rise_c};  // no recorded range: a generous warm-up
  }
  std::vector<double> ambients{std::numeric_limits<double>::quiet_NaN()};
  if (!axis.ambient_sensor.empty() && std::isfinite(axis.ambient_baseline_c))
    ambients = {axis.ambient_baseline_c - o.ambient_margin_c, axis.ambient_baseline_c,
                axis.ambient_baseline_c + o.ambient_margin_c};

  // The motion-heat input (AxisModel::motion_lag_s) from standstill to the highest the gains were
  // fitted at (their envelope; without one, a rapid 20 m/min held for good).
  std::vector<double> motions{0.0};
  if (axis.HasMotionHeat()) {
    double hi = 0;
    for (const auto& dm : axis.directions)
      for (const auto& g : dm.thermal)
        if (g.key_rise_range_c.size() > keys) hi = std::max(hi, g.key_rise_range_c[keys][1]);
    motions.push_back(hi > 0 ? hi : 20.0);
  }

  double worst = 0;
  std::vector<double> temps(keys);
  for (Direction d : {Direction::kForward, Direction::kReverse}) {
    const DirectionModel& dm = axis.For(d);
    std::vector<CoolantState> coolants{CoolantState::kOff};
    for (const auto& g : dm.thermal)
      if (std::find(coolants.begin(), coolants.end(), g.coolant) == coolants.end()) coolants.push_back(g.coolant);
    const auto xs = Positions(dm.geometric);
    // The key sensors of one axis warm and cool together (nut, bearing, motor of one drive): the
    // envelope takes them all cool or all hot, not in every combination (a hot nut beside a cold
    // motor never happened in the fit and would inflate the bound several times).
    for (std::size_t level = 0; level < 2; ++level) {
      for (std::size_t k = 0; k < keys; ++k) temps[k] = levels[k][level];
      for (double amb : ambients)
        for (CoolantState c : coolants)
          for (double motion : motions) {
            const ThermalState ts{std::span<const double>(temps), amb, c, true, motion};
            for (double x : xs) {
              const double corr = std::fabs(CorrectionUm(Predict(axis, x, d, ts)));
              if (std::isfinite(corr)) worst = std::max(worst, corr);
            }
          }
    }
  }
  return worst;
}

}  // namespace

CompensationBound DeriveCompensationBound(const AxisModel& axis, const CompensationBoundOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw std::invalid_argument("CompensationBoundOptions: " + why);
  // A fallback model (a key sensor lost) drives the same axis: its corrections must pass too.
  double worst = LargestCorrection(axis, o);
  for (const auto& f : axis.fallbacks) worst = std::max(worst, LargestCorrection(f, o));
  CompensationBound b;
  b.model_max_um = worst;
  const double wanted = std::ceil(worst * (1 + o.margin_fraction) / o.round_to_um) * o.round_to_um;
  b.bound_um = std::max(o.min_bound_um, wanted);
  if (b.bound_um > o.controller_limit_um) {
    b.bound_um = o.controller_limit_um;
    b.limited_by_controller = true;
  }
  return b;
}

}  // namespace trueaxis::model
