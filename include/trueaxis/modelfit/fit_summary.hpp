#pragma once
// What the automatic fit did and how well (Ceres-style BriefReport/FullReport).
// Every number a metrology engineer would ask about: the degree and why, the
// cross-validated errors, the key sensors and why, Px and ρ and where they came
// from, residual RMS / max per state, and every fallback taken as a warning.
#include <array>
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/modelfit/fit_diagnostics.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/polynomial_fit.hpp"

namespace trueaxis::model {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct StateFitStats {
  std::string label;
  std::string path;
  StateKind kind = StateKind::kUnknown;
  CoolantState coolant = CoolantState::kOff;
  bool used_for_thermal = false;  // took part in the gain fit
  std::size_t points = 0;
  std::vector<double> mean_key_rise_c;           // parallel to the axis' key sensors
  double mean_ambient_rise_c = kNaN;
  std::array<double, 2> tan_beta_um_per_mm{kNaN, kNaN};  // per-state slope about Px (seed stage 1), fwd/rev
  double uncorrected_rms_um = 0, uncorrected_max_um = 0;  // measured deviation itself
  double geometric_only_rms_um = 0;                       // measured − Er(x)
  double residual_rms_um = 0, residual_max_um = 0;        // measured − full model
};

struct SelectionStep {
  std::vector<std::string> keys;  // the set after this step
  double cv_rms_um = kNaN;        // leave-one-state-out CV of the thermal residual
  std::string note;
};

struct DirectionFitStats {
  GeometricError::Kind kind = GeometricError::Kind::kPolynomial;
  std::size_t targets = 0;
  int runs = 0;
  DegreeSelection degree;          // polynomial: the candidates and the rule (also computed before an auto → table)
  std::string choice;              // polynomial or table, and why
  double geometric_fit_rms_um = kNaN;  // fit of the cold target means
  double geometric_cv_rms_um = kNaN;   // leave-one-target-out
  double table_cv_rms_um = kNaN;       // the seed-002 table's CV, for comparison
  // Leave-one-RUN-out CV (polynomial_fit.hpp): what `auto` decides by when there are >= 3 runs.
  double table_loro_rms_um = kNaN, polynomial_loro_rms_um = kNaN;
};

// One fallback model fitted without a sensor (FitOptions::fallback_models), as a table row.
struct FallbackFitStats {
  std::string without;                 // the sensor it does without
  std::vector<std::string> partners;   // its redundant probes, left out with it
  std::string how;                     // "keys re-chosen" or "the model's other keys"
  std::vector<std::string> key_sensors;
  bool room_term = true;
  double cv_rms_um = kNaN;             // its LOSO CV RMS
  bool kept = false;                   // among the fallbacks the model keeps (the best by CV)
};

struct AxisFitSummary {
  std::string axis;
  std::string cold_source;
  std::array<DirectionFitStats, 2> directions;
  bool thermal_fitted = false;
  std::vector<std::string> candidate_sensors;
  std::string candidate_note;             // e.g. which sensors of other axes were left out
  std::vector<std::string> key_sensors;
  std::string key_selection_reason;
  std::vector<SelectionStep> selection_steps;
  double thermal_cv_rms_um = kNaN;       // with the chosen keys (and the chosen lag)
  // Thermal lag τ of the key sensors (one τ per axis, thermal_lag.hpp): each grid value's
  // LOSO CV RMS with the chosen keys, the chosen τ (0 = no lag) and why.
  std::vector<std::array<double, 2>> lag_candidates;  // {tau_s, cv_rms_um}
  double key_lag_s = 0;
  std::string lag_reason;
  // The motion-heat input (FitOptions::motion_lag_grid_s): τ kept (0: none) and why, each τ's CV.
  double motion_lag_s = 0;
  std::string motion_reason;
  std::vector<std::array<double, 2>> motion_candidates;  // {tau_s, cv_rms_um}
  bool key_offsets = false;         // each key's own pivot (FitOptions::key_offsets)
  std::string key_offsets_reason;
  double no_thermal_cv_rms_um = kNaN;    // residual RMS with no thermal term (step 0)
  double reference_position_mm = 0;
  std::string reference_source;          // "option", "metadata", "fitted ...", "default ..."
  double rho_um_per_mm_per_c = 0;
  std::string rho_source;
  bool rho_from_cte = false;  // ρ = −cte/1000, the physical soak (holds in every season)
  // ρ the calibration's room changes alone would fit, when ρ came from the CTE (NaN otherwise).
  double rho_fitted_for_check = kNaN;
  // The room temperatures the fit saw (°C; NaN without an ambient sensor): the model's ρ holds
  // beyond them when it is the physical soak (from the CTE), its fitted terms do not.
  std::array<double, 2> room_range_c{kNaN, kNaN};
  std::vector<std::string> coolant_notes;  // how each coolant entry was fitted
  std::vector<std::string> fallback_notes; // the fallback models (FitOptions::fallback_models), in order
  std::vector<FallbackFitStats> fallbacks; // ... those fitted, as data
  std::vector<StateFitStats> states;
  // The residual's shape per state, structure no sensor follows, key sensors' shares (fit_diagnostics.hpp).
  ResidualDiagnosis diagnosis;
};

struct FitSummary {
  std::vector<AxisFitSummary> axes;
  std::vector<std::string> warnings;

  // A few lines: per axis degree, keys, CV errors, worst state residual, warnings count.
  std::string BriefReport() const;
  // Everything, as a plain-text table report.
  std::string FullReport() const;
  // Stored as CompositeModel::fit_summary (docs/model-file.md).
  nlohmann::json ToJson() const;
};

}  // namespace trueaxis::model
