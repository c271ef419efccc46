#pragma once
// Options of the automatic composite-model fit (Ceres-style: defaults that
// work, IsValid() says what is wrong). See model_fit.hpp for the method.
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::model {

struct FitOptions {
  // kPolynomial: seed 000's polynomial (degree by CV); kTable: seed 002's sampled table;
  // kAuto: the polynomial unless its residuals at the targets are systematic — fit RMS above
  // auto_systematic_factor × the noise of the target means (a repeatable pattern a smooth
  // curve cannot follow, e.g. the screw's lead harmonics) — and the table interpolates no
  // worse (table LOTO CV ≤ auto_table_cv_ratio × the polynomial's). Decided per direction.
  enum class Geometric { kPolynomial, kTable, kAuto };
  Geometric geometric = Geometric::kAuto;
  double auto_systematic_factor = 3.0;
  double auto_table_cv_ratio = 1.25;
  // With >= 3 cold runs, `auto` decides by leave-one-run-out CV instead (polynomial_fit.hpp): the
  // table is chosen when its held-out-run RMS is below (1 − this margin) × the polynomial's.
  double auto_table_run_margin = 0.05;
  int max_degree = 8;                            // highest polynomial degree tried (capped at targets − 2)

  // Reference point Px (where the thermal error is zero: the screw's fixed
  // bearing). NaN: `# reference_position_mm:` metadata of the cold file, else
  // fitted as the common pivot of the heated states' residual fans.
  double reference_position_mm = std::numeric_limits<double>::quiet_NaN();

  // Key sensors. Empty: chosen automatically (forward stepwise selection
  // under leave-one-state-out CV). Non-empty: used as given, every file must have them.
  std::vector<std::string> key_sensors;
  int max_key_sensors = 3;
  // A sensor is not added when it improves the CV error by less than this fraction.
  double min_cv_improvement = 0.05;
  // Two candidates whose per-point rises correlate more than this are collinear:
  // only the better one can be chosen.
  double max_key_correlation = 0.98;
  // Ridge on the gains of every key after the first (the first is the best single key, or the
  // first one given): the least squares minimises |A·c − b|² + λ·Σ_{j≥2} c_j², with A's columns
  // scaled to unit norm, so λ is dimensionless and damps the directions of key space along which
  // the calibration states varied by less than about λ of a column's norm². Two keys that rise
  // together (nut and bearing over a warm-up) otherwise get large gains of opposite sign: their
  // difference fits the campaign's transients and swings on the working day's other mixes.
  // 0: plain least squares (seed 000). Default chosen on the machine zoo and checked on
  // descriptions not in it (bench/results/zoo.md, "Secondary keys shrunk").
  double secondary_key_ridge = 0.003;
  // Each key's own pivot (ThermalGains::offset_um_per_c): besides its slope about the common Px,
  // each key's rise (and the room's change) also shifts the error over the whole travel. kAuto:
  // kept when, with the keys and lag chosen, it lowers the leave-one-state-out CV by
  // min_cv_improvement; kOn / kOff: always / never (kOff = the seed's form).
  enum class KeyOffsets { kAuto, kOn, kOff };
  KeyOffsets key_offsets = KeyOffsets::kAuto;
  // Sensors named for another axis ("y_nut" while fitting X) are not candidates
  // when the files name sensors per axis at all (some sensor starts with "x_"):
  // a warm-up that heats every axis at once makes them correlate with this
  // axis' error without causing it, and a different warm-up path would break
  // that correlation. Shared sensors (ambient, bed, ...) stay candidates.
  bool own_axis_sensors_only = true;
  // Sensors that are never key-sensor candidates (a fallback model's lost key, a sensor known bad).
  std::vector<std::string> excluded_sensors;
  // Redundant probes: sensors at one place (two probes on a nut), which the temperature pipeline
  // checks against each other and, when they disagree, loses together (signal `disagreement`).
  // A fallback fitted without one of them does without its partners too.
  std::vector<std::vector<std::string>> redundant_groups;
  // Thermal lag of the key sensors (thermal_lag.hpp): the τ values (seconds) tried, after the
  // keys are chosen, by the same leave-one-state-out CV, the lag applied along each file's time
  // series (through the logged history when the manifest has one). The best τ > 0 is kept only
  // when it lowers the CV by min_lag_cv_improvement. {} or {0}: no lag.
  std::vector<double> key_lag_grid_s = {0, 120, 300, 600, 1200, 2400};
  // Lower than min_cv_improvement because τ is one parameter per axis, where a key sensor adds a
  // gain per direction and coolant state (set after the VMC-850 study, bench/results/modelfit.md).
  double min_lag_cv_improvement = 0.01;
  // With a lag kept: the factors tried for a falling key's longer τ (AxisModel::key_lag_fall_factor),
  // kept by the same CV rule. {1}: one τ both ways (the lag as before). Not with per_key_lag.
  std::vector<double> key_lag_fall_grid = {1, 2, 4, 8};
  // After the common τ, try each key's own τ (coordinate descent over the grid, two passes). Off by
  // default: on the machine zoo the per-key τ chosen by the campaign's LOSO CV did not carry over
  // to the held-out working day (gantry2000 X afternoon 51 → 70 µm, bench/results/zoo.md).
  bool per_key_lag = false;
  // The motion-heat input (AxisModel::motion_lag_s, motion_heat.hpp): the lag τ values (s) tried for
  // the axis's feed as one more key, after the keys, their lag and pivots are chosen, by the same
  // leave-one-state-out CV; the best is kept when it lowers the CV by min_cv_improvement. Tried only
  // when every state's history has the axis's travelled path (the machine log's <axis>_travel_mm).
  // {} or {0}: never (the seed's form).
  std::vector<double> motion_lag_grid_s = {600, 900, 1200, 1800, 2400, 3600, 5400};
  // auto: kept by the CV rule above; on: the best τ of the grid kept whatever the CV says (when
  // every state has the travel); off: not tried. Auto by default since stop 34, with the campaign
  // that identifies it (sim::CampaignOptions: warm-up machining between tests, min_warmup_per_test
  // 0.5, and coolant sessions in both visits): machine zoo seeds 1–5 647 of 650 rows under the must
  // line against 629, 48 drawn machines 530 of 540 against 532, sum of A_on −5 %
  // (bench/results/zoo.md). On the older campaign the CV could not rank it (910 against 911 of 930).
  enum class MotionHeat { kAuto, kOn, kOff };
  MotionHeat motion_heat = MotionHeat::kAuto;
  // Coolant gains: with keys + 1 states or more a coolant gets its own gains; when true, only if
  // they predict a held-out coolant state better than the off gains × one factor (off by default:
  // on the machine zoo both forms extrapolate badly from 4 states of one session, and the factor
  // form was worse; the prediction's slope envelope guards against the wild case instead).
  bool coolant_form_by_cv = false;
  // A coolant's own gains keep the off-coolant response to a soak: the sum of the key gains (and of
  // the keys' and the room's shifts) held at the off gains' (the soaked machine with the coolant at
  // the room's temperature expands as it does dry; one season's coolant states cannot tell).
  bool coolant_soak_constraint = false;
  // The envelope of the thermal slope each gains entry may give (ThermalGains::min/max_tan_beta):
  // the range over the fit's states of that coolant (and 0, the cold state), widened on both sides
  // by this fraction of its width. Negative: no envelope (the model extrapolates freely).
  double tan_beta_margin = 0.25;
  // The coolant's memory (thermal_state.hpp, AxisModel::key_loss_s): the loss time constants (s)
  // tried for each coolant state in the data, with the lagged keys and one set of gains for every
  // state; kept when its LOSO CV over all states beats gains per coolant state. 0 = shared gains
  // without loss. {} (the default): not tried, gains per coolant state. Opt in with
  // CoolantMemoryGridS(). Off by default since the slower fall (key_lag_fall_factor): the CV, judged
  // on the campaign's one coolant session from a cold machine, kept it where the working day's
  // coolant over a warm machine then did worse; without it the machine zoo keeps more rows under
  // the must line (seeds 1–5: 629 against 627 of 650, goal 497 against 483, sum of A_on −0…−2 %)
  // and so do seven descriptions not in the repository (bench/results/zoo.md).
  std::vector<double> coolant_loss_grid_s = {};
  static std::vector<double> CoolantMemoryGridS() { return {0, 600, 1200, 2400, 4800, 9600}; }
  // ... and only when, held out, the dry states are predicted within this fraction of their own
  // gains' LOSO CV (one set of gains is a compromise over every state). 1 = twice their CV: on the
  // machine zoo (seeds 1, 3, 5) 0.25 kept fewer rows under the must line (bench/results/zoo.md).
  double coolant_memory_off_tolerance = 1.0;
  // Fewer heated (or ambient) off-coolant states than this → geometric-only model with a warning.
  int min_thermal_states = 2;

  // Ambient sensor for the ρ·ΔT_env term. Empty: the first sensor named
  // ambient/air/env/environment/room present in every file; "none": no ambient term.
  std::string ambient_sensor;
  // ρ (µm per mm per °C) in the seed's form ΔEr = ρ·ΔT_env·(Px − P0). NaN: −cte/1000 when the CTE
  // of the axis's feedback is known (cte_um_per_m_c, else the cold file's `# cte_um_per_m_c:`): a
  // machine soaked in a warmer room grows by its feedback's expansion, in every season, while a ρ
  // fitted on one season's daily swings carries how the structure lagged the room on those days
  // and misses other seasons (bench/results/zoo.md, one-season campaigns). Without the CTE: fitted
  // when the room temperature varies by ≥ min_ambient_range_c over the states (warned: it
  // extrapolates to other seasons), else 0 (warned).
  double rho_um_per_mm_per_c = std::numeric_limits<double>::quiet_NaN();
  // CTE of the axis's position feedback, µm/m/°C: the ball screw's with a rotary encoder (steel
  // about 11.5), the scale's with a linear scale; for laser files that do not record it. NaN: the
  // cold file's `# cte_um_per_m_c:`.
  double cte_um_per_m_c = std::numeric_limits<double>::quiet_NaN();
  // Fit ρ from the room's changes over the states even when the CTE is known (the rule before the
  // physical soak; for comparison, or a machine whose structure does not soak as its feedback).
  bool fit_rho_with_cte = false;
  double min_ambient_range_c = 1.0;

  // Fallback models (AxisModel::fallbacks): an axis with key sensors is fitted again without each
  // one of them, twice (its keys re-chosen from the remaining candidates; the model's other keys),
  // and without its ambient sensor (keys re-chosen), every other option the same, so the
  // compensator keeps a thermal part when a key sensor dies — also when the model has a single key.
  // Ordered by their LOSO CV. false: none.
  bool fallback_models = true;
  // The most fallbacks kept per axis, the best by CV (1 … AxisModel::kMaxFallbacks); the others are
  // named in the fit summary's fallback notes.
  int max_fallback_models = static_cast<int>(AxisModel::kMaxFallbacks);

  // Used when a file has no `# axis:` line (empty: such a file is an error).
  std::string default_axis;

  // Stamped into the model as created_utc: the caller's clock (the fit itself reads none, so the
  // same inputs give the same model). Empty: left empty.
  std::string created_utc;

  // Told what the fit is doing (`done` of `total` model fits, and which), e.g. for a progress line;
  // the fit's result does not depend on it. Empty: nothing told.
  std::function<void(std::size_t done, std::size_t total, const std::string& what)> progress;

  bool IsValid(std::string* why) const;
};

}  // namespace trueaxis::model
