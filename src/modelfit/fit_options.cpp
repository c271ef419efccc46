#include "trueaxis/modelfit/fit_options.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::model {

bool FitOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (max_degree < 1 || max_degree > 15) return fail(fmt::format("max_degree {} must be within 1 … 15", max_degree));
  if (!(auto_systematic_factor > 0)) return fail("auto_systematic_factor must be > 0");
  if (!(auto_table_cv_ratio > 0)) return fail("auto_table_cv_ratio must be > 0");
  if (!(auto_table_run_margin >= 0 && auto_table_run_margin < 1)) return fail("auto_table_run_margin must be in [0, 1)");
  if (std::isinf(reference_position_mm)) return fail("reference_position_mm must be finite (or NaN for automatic)");
  if (!std::isnan(reference_position_mm))
    if (auto implausible = ImplausiblePositionMm(reference_position_mm)) return fail("reference_position_mm: " + *implausible);
  if (max_key_sensors < 0 || max_key_sensors > 8)
    return fail(fmt::format("max_key_sensors {} must be within 0 … 8", max_key_sensors));
  if (!(min_cv_improvement >= 0 && min_cv_improvement < 1))
    return fail("min_cv_improvement must be within [0, 1)");
  if (!(max_key_correlation > 0 && max_key_correlation <= 1)) return fail("max_key_correlation must be within (0, 1]");
  if (!(secondary_key_ridge >= 0) || !std::isfinite(secondary_key_ridge))
    return fail("secondary_key_ridge must be a finite number >= 0 (0: plain least squares)");
  if (min_thermal_states < 1) return fail("min_thermal_states must be >= 1");
  if (max_fallback_models < 1 || max_fallback_models > static_cast<int>(AxisModel::kMaxFallbacks))
    return fail(fmt::format("max_fallback_models {} must be within 1 … {}", max_fallback_models, AxisModel::kMaxFallbacks));
  if (std::isinf(rho_um_per_mm_per_c)) return fail("rho_um_per_mm_per_c must be finite (or NaN for automatic)");
  if (!std::isnan(rho_um_per_mm_per_c))
    if (auto implausible = ImplausibleExpansionUmPerMmPerC(rho_um_per_mm_per_c))
      return fail("rho_um_per_mm_per_c: " + *implausible);
  if (std::isinf(cte_um_per_m_c)) return fail("cte_um_per_m_c must be finite (or NaN: from the files)");
  if (!std::isnan(cte_um_per_m_c))
    if (auto implausible = ImplausibleCteUmPerMC(cte_um_per_m_c)) return fail("cte_um_per_m_c: " + *implausible);
  if (!(min_ambient_range_c > 0)) return fail("min_ambient_range_c must be > 0");
  for (double tau : key_lag_grid_s)
    if (!(tau >= 0) || !std::isfinite(tau)) return fail("key_lag_grid_s values must be finite seconds >= 0");
  for (double tau : motion_lag_grid_s)
    if (!(tau >= 0) || !std::isfinite(tau)) return fail("motion_lag_grid_s values must be finite seconds >= 0");
  for (double f : key_lag_fall_grid)
    if (!(f >= 1) || !std::isfinite(f)) return fail("key_lag_fall_grid values must be finite factors >= 1");
  if (!(min_lag_cv_improvement >= 0 && min_lag_cv_improvement < 1))
    return fail("min_lag_cv_improvement must be within [0, 1)");
  if (!(coolant_memory_off_tolerance >= 0)) return fail("coolant_memory_off_tolerance must be >= 0");
  for (double tau : coolant_loss_grid_s)
    if (!(tau >= 0) || !std::isfinite(tau)) return fail("coolant_loss_grid_s values must be finite seconds >= 0");
  if (std::isnan(tan_beta_margin) || tan_beta_margin > 10) return fail("tan_beta_margin must be <= 10 (negative: no envelope)");
  std::set<std::string> seen;
  for (const auto& k : key_sensors) {
    if (k.empty()) return fail("key_sensors has an empty name");
    if (!seen.insert(k).second) return fail(fmt::format("key sensor '{}' is given twice", k));
    if (k == ambient_sensor) return fail(fmt::format("'{}' is the ambient sensor; it cannot also be a key sensor", k));
  }
  return true;
}

}  // namespace trueaxis::model
