#pragma once
// The composite geometric + thermal error model of seed 000 (MISSION M4, M5):
//
//   Er(x, T) = Er(x) + tanβ·(Px − P0) + ρ·ΔT_env·(Px − P0)
//   tanβ     = Σ_i k_i·ΔT_i (+ k_m·M)  (k per coolant state, ΔT_i rise of key sensor i; M the axis's
//                                       motion-heat input when the model has one, AxisModel::motion_lag_s)
//
// with Er(x) the cold-state error of one direction of approach, Px the
// reference point, P0 the current machine coordinate. One AxisModel per axis,
// with one DirectionModel per direction (forward '+', reverse '-').
//
// Sign convention (docs/sign-convention.md): every *_error_um / Predict()
// value is an ERROR = actual − commanded position. The correction to add to
// the command is its negative: CorrectionUm(p) = −p.total_um.
//
// Predict() is pure, allocation-free and safe to call from the real-time
// cycle. The JSON form is docs/model-file.md (model_json.hpp).
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/direction.hpp"

namespace trueaxis::model {

// How far beyond a measured range (AxisModel::measured_range_mm, a pitch table's) a position may
// lie before it counts as outside: the calibration cycle's shortest reversal at the travel's ends
// (pitch::FineCycleOptions::end_margin_mm) stays inside it. Within it the end value is held too.
inline constexpr double kMeasuredRangeToleranceMm = 0.5;

// Er(x) of one direction.
struct GeometricError {
  enum class Kind { kPolynomial, kTable };
  Kind kind = Kind::kPolynomial;
  // kPolynomial: Er = Σ c_j·u^j with u = (x − center_mm) / half_span_mm
  // (normalised for conditioning), c_j in µm.
  double center_mm = 0;
  double half_span_mm = 1;
  std::vector<double> coefficients_um;
  // kTable (seed 002): ascending positions, linear interpolation between
  // samples, the end value held beyond the ends.
  std::vector<double> table_position_mm;
  std::vector<double> table_error_um;

  double Evaluate(double position_mm) const;
};

// tanβ gains for one coolant working state (the seed's look-up table).
struct ThermalGains {
  CoolantState coolant = CoolantState::kOff;
  // Parallel to AxisModel::key_sensors, then (when the model has a motion-heat input,
  // AxisModel::HasMotionHeat) one more: the gain of M, µm/mm per m/min. The same holds for
  // key_rise_range_c (M's range in m/min) and KeyShifts::offset_um_per_c (µm per m/min).
  std::vector<double> k_um_per_mm_per_c;
  double offset_um_per_mm = 0;            // constant term of tanβ (0 in the seed's form)
  // The envelope these gains were fitted in (issue 10), both optional:
  //  - key_rise_range_c (JSON "key_rise_range_c", [low, high] °C per key sensor): the rises ΔT_i
  //    over the fit's states of this coolant (and 0, the cold state), widened by a margin;
  //  - min/max_tan_beta (JSON "tan_beta_range_um_per_mm"): the range of Σ k_i·ΔT_i over them.
  // Beyond them the gains would extrapolate past anything measured (a few states of one warm-up
  // can give large gains of opposite sign that swing on hotter or other mixes of temperatures):
  // Predict holds each rise, then tanβ, at the nearer end and flags the prediction
  // (Prediction::tan_beta_limited), which the runtime raises as an alarm. Empty / ±inf: none.
  std::vector<std::array<double, 2>> key_rise_range_c;
  double min_tan_beta_um_per_mm = -std::numeric_limits<double>::infinity();
  double max_tan_beta_um_per_mm = std::numeric_limits<double>::infinity();
  bool HasTanBetaRange() const { return std::isfinite(min_tan_beta_um_per_mm) || std::isfinite(max_tan_beta_um_per_mm); }
};

// Each key's own pivot for one gains entry (issue 10, FitOptions::key_offsets): a key's rise also
// shifts the error by offset_um_per_c[i]·ΔT_i over the whole travel, so key i pivots at
// Px + offset_i/k_i instead of the common Px (a heated screw end beyond the travel, a growing
// bearing housing); ambient_offset_um_per_c the same for the room's change ΔT_env.
struct KeyShifts {
  std::vector<double> offset_um_per_c;  // parallel to AxisModel::key_sensors; empty = none
  double ambient_offset_um_per_c = 0;
};

struct DirectionModel {
  GeometricError geometric;
  std::vector<ThermalGains> thermal;  // one entry per coolant state fitted; may be empty
  // Gains for `coolant`; falls back to the kOff entry, then the first entry; nullptr if none.
  const ThermalGains* GainsFor(CoolantState coolant) const;
};

struct AxisModel {
  std::string axis;                    // "X", "Y", "Z", ...
  double reference_position_mm = 0;    // Px: where the thermal error is zero
  std::vector<std::string> key_sensors;
  std::vector<double> baseline_temp_c; // per key sensor: the temperatures Er(x) was measured at
  std::string ambient_sensor;          // empty: no ambient adjustment
  double ambient_baseline_c = std::numeric_limits<double>::quiet_NaN();
  double rho_um_per_mm_per_c = 0;      // ρ: ambient expansion, µm per mm per °C
  // How ΔT_i of a key sensor is measured (added by the fitter, docs/model-file.md):
  //   false: ΔT_i = T_i − baseline_i (the seed's form; the default)
  //   true:  ΔT_i = (T_i − baseline_i) − (T_amb − ambient_baseline_c), the rise ABOVE AMBIENT,
  //          so a uniform soak at another room temperature moves only the ρ term and is not
  //          counted twice. Needs ambient_sensor; with no ambient reading (NaN) Predict falls
  //          back to the plain rise.
  bool key_rise_above_ambient = false;
  // First-order lag time constant per key sensor, seconds (thermal_lag.hpp; JSON "key_lag_s").
  // Empty or 0: no lag. The caller (runtime, predict --measurement) lags the readings
  // with LagStep() before they enter Predict(); Predict itself takes the lagged values.
  std::vector<double> key_lag_s;
  // While a key's reading falls below its lagged value (and no coolant loss draws it), the lag's τ
  // is this many times longer (JSON "key_lag_fall_factor"; 1 or absent: one τ both ways). The
  // screw keeps its heat after the nut's friction stops: the nut sensor cools faster than the
  // screw it stands for (issue 10; chosen by the fit's CV, FitOptions::key_lag_fall_grid).
  double key_lag_fall_factor = 1;
  // Per coolant state (indexed by CoolantState), per key sensor: the time constant (s) with which
  // that coolant draws the key's effective temperature towards the room (thermal_state.hpp,
  // JSON "key_loss_s": {"flood": [...]}). Empty or 0: no loss (the plain lag).
  std::array<std::vector<double>, 4> key_loss_s;
  // Per key sensor: the lowest and highest reading in the fit's measurements (°C). A prediction
  // outside this range is an extrapolation and is flagged (predict warns). Empty: not recorded.
  std::vector<std::array<double, 2>> key_fitted_range_c;
  // The motion-heat input (issue 10's observer of the screw's heat driven by the axis's own motion):
  // M = the axis's feed |dP0/dt| in m/min through a first-order lag of this time constant (s; JSON
  // "motion_heat": {"tau_s": …}). It enters tanβ as one more key with rise M (gains arrays one
  // longer). 0: none (the seed's form). Live input: the axis position every cycle (thermal_state.hpp).
  double motion_lag_s = 0;
  bool HasMotionHeat() const { return motion_lag_s > 0; }
  // The number of gains per entry: the key sensors, and M.
  std::size_t GainCount() const { return key_sensors.size() + (HasMotionHeat() ? 1 : 0); }
  std::array<DirectionModel, 2> directions;

  // τ of key sensor i (0 when not given).
  double KeyLagS(std::size_t i) const { return i < key_lag_s.size() ? key_lag_s[i] : 0.0; }
  // τ of key sensor i for one step from `state_c` towards the reading `raw_c` (no coolant loss).
  double KeyLagS(std::size_t i, double state_c, double raw_c) const {
    return raw_c < state_c ? key_lag_fall_factor * KeyLagS(i) : KeyLagS(i);
  }
  double KeyLossS(std::size_t i, CoolantState c) const {
    const auto& v = key_loss_s[static_cast<std::size_t>(c) % key_loss_s.size()];
    return i < v.size() ? v[i] : 0.0;
  }
  bool HasKeyLag() const {
    for (double t : key_lag_s)
      if (t > 0) return true;
    return false;
  }  // indexed by DirectionIndex()

  const DirectionModel& For(Direction d) const { return directions[DirectionIndex(d)]; }
  // Each key's own pivot per direction, parallel to directions[d].thermal (empty = none, the seed's
  // form). Kept here, not in ThermalGains: the compensator's cycle slowed by ~4 ns per axis when
  // ThermalGains grew (bench/results/runtime.md).
  std::array<std::vector<KeyShifts>, 2> key_shifts;
  // The lowest and highest ambient reading in the fit's measurements (°C; JSON
  // "ambient_fitted_range_c"). A room outside it is an extrapolation of the ρ term (and of the
  // rises above ambient): Predict flags it (Prediction::ambient_extrapolated) but does not hold
  // it — a machine soaked in a colder room really is shorter. NaN: not recorded (older files).
  std::array<double, 2> ambient_fitted_range_c{std::numeric_limits<double>::quiet_NaN(),
                                               std::numeric_limits<double>::quiet_NaN()};
  // Whether the ambient sensor changes what the model predicts: a ρ term, or a thermal part (its
  // keys' rise above ambient, the coolant's pull towards the room, a room pivot). A geometric-only
  // model that merely records the room sensor of its measurement (ρ = 0, no keys) does not need it.
  bool AmbientInUse() const {
    if (ambient_sensor.empty()) return false;
    if (rho_um_per_mm_per_c != 0 || !key_sensors.empty() || HasMotionHeat()) return true;
    for (const auto& per_direction : key_shifts)
      for (const auto& ks : per_direction)
        if (ks.ambient_offset_um_per_c != 0) return true;
    return false;
  }
  // The positions its geometric part was measured over (JSON "measured_range_mm": [first, last]
  // target), the range it vouches for: written with a pitch table (`pitch into-model`,
  // docs/pitch-error-file.md). Beyond it by more than kMeasuredRangeToleranceMm, Predict holds the
  // geometric part at the nearer end and flags the prediction (Prediction::position_outside_range;
  // the runtime's alarm outside_measured_range). NaN: not recorded (never flagged, as before).
  std::array<double, 2> measured_range_mm{std::numeric_limits<double>::quiet_NaN(),
                                          std::numeric_limits<double>::quiet_NaN()};
  bool HasMeasuredRange() const { return std::isfinite(measured_range_mm[0]) && std::isfinite(measured_range_mm[1]); }
  bool AmbientOutsideFittedRange(double ambient_c) const {
    return ambient_c < ambient_fitted_range_c[0] - 1e-9 || ambient_c > ambient_fitted_range_c[1] + 1e-9;
  }  // false for NaN (either side)
  // Models of this axis fitted on the same data without one of its key sensors or its ambient
  // sensor (JSON "fallbacks"; their keys chosen from the other sensors), in order of preference:
  // when such a sensor is lost, the compensator goes on with the first whose sensors all read,
  // instead of dropping the thermal part (docs/model-file.md, "Fallback models"). Each does without
  // at least one of these keys or the ambient sensor and has no fallbacks of its own.
  std::vector<AxisModel> fallbacks;
  // Two per lost sensor (its keys re-chosen, and the model's other keys) for up to three keys and
  // the room sensor: the most a model file may hold per axis (the runtime keeps a state each).
  static constexpr std::size_t kMaxFallbacks = 8;
  // A fallback's: the sensor of the axis's model it was fitted without (JSON "replaces"; empty in
  // the model itself and in older files). When that sensor is lost, the compensator averages the
  // fallbacks that replace it and can run (docs/model-file.md, "Fallback models").
  std::string replaces;
  // The shifts of gains entry `g` of direction `d`; nullptr when it has none.
  const KeyShifts* ShiftsFor(Direction d, const ThermalGains* g) const {
    const auto& v = key_shifts[DirectionIndex(d)];
    const auto& t = directions[DirectionIndex(d)].thermal;
    if (v.empty() || !g || g < t.data()) return nullptr;
    const auto i = static_cast<std::size_t>(g - t.data());
    return i < v.size() && !v[i].offset_um_per_c.empty() ? &v[i] : nullptr;
  }
};

// One earlier revision of a model this one was re-fitted from (oldest first).
struct LineageEntry {
  int revision = 0;
  std::string sha256;       // of that model file's bytes
  std::string created_utc;
};

// Where a source file of the fit came from (lineage).
struct SourceRecord {
  std::string path;
  std::string sha256;
  std::string state;  // "cold", "warm", "ambient", "coolant:flood", ...
  std::string coolant;  // coolant state during the measurement ("off", "flood", ...; "" unknown)
  std::string axis;     // axis the file measured ("" unknown)
  // The campaign temperature log the state's history (thermal lag) came from, its hash and the
  // measurement's start on the log's clock; empty / NaN when the fit had none for this file.
  std::string temperature_log;
  std::string temperature_log_sha256;
  double start_time_s = std::numeric_limits<double>::quiet_NaN();
};

struct CompositeModel {
  static constexpr int kFormatVersion = 1;
  int format_version = kFormatVersion;
  std::string machine;
  std::string created_utc;
  std::string generator;              // e.g. "trueaxis 0.1.0 fit"
  int revision = 1;                   // increases by one on every re-fit
  std::string parent_sha256;          // hash of the model this re-fit replaced, empty if none
  std::vector<SourceRecord> sources;
  std::vector<LineageEntry> lineage;  // every ancestor, oldest first; the parent is the last
  std::vector<AxisModel> axes;
  nlohmann::json fit_summary = nlohmann::json::object();  // statistics, free form (docs/model-file.md)

  const AxisModel* FindAxis(const std::string& name) const;
};

// The name the motion-heat input goes by where inputs are given by name (export --temp, predict).
inline constexpr const char* kMotionHeatName = "motion_m_per_min";

// The thermal state the prediction is made for.
struct ThermalState {
  std::span<const double> key_temp_c;  // current (already lagged, AxisModel::key_lag_s) temperatures, parallel to key_sensors
  double ambient_c = std::numeric_limits<double>::quiet_NaN();  // NaN: no ambient adjustment
  CoolantState coolant = CoolantState::kOff;
  bool use_thermal = true;             // false: geometric part only (sensor-fault fallback)
  // The motion-heat input M (m/min, AxisModel::motion_lag_s; AxisThermalState::motion_m_per_min).
  // Used only by a model with one; NaN there: the thermal part is 0 (geometric only), as a NaN key.
  double motion_m_per_min = 0;
};

struct Prediction {
  double geometric_um = 0;
  double thermal_um = 0;
  double ambient_um = 0;
  double tan_beta_um_per_mm = 0;
  double total_um = 0;  // error = geometric + thermal + ambient
  // A key rise or tanβ lay outside its gains' fitted envelope (ThermalGains::key_rise_range_c,
  // min/max_tan_beta_um_per_mm) and was held at the nearer end: the model was asked to
  // extrapolate (an alarm for the user).
  bool tan_beta_limited = false;
  // The room temperature lay outside the fit's (AxisModel::ambient_fitted_range_c): the ρ term was
  // extrapolated, not held (an alarm for the user, as tan_beta_limited).
  bool ambient_extrapolated = false;
  // The position lay beyond the axis's measured range (AxisModel::measured_range_mm) by more than
  // kMeasuredRangeToleranceMm: the geometric part was held at the nearer end (an alarm for the user).
  bool position_outside_range = false;
};

// Predicted error at `position_mm` approached in `direction`. Pure; no allocation.
// A key temperature that is NaN makes the thermal part 0 (geometric only).
Prediction Predict(const AxisModel& axis, double position_mm, Direction direction, const ThermalState& state);

inline double CorrectionUm(const Prediction& p) { return -p.total_um; }

}  // namespace trueaxis::model
