#pragma once
// Automatic fitting of the composite model of seed 000 (MISSION M4, M5):
//
//   Er(x, T) = Er(x) + tanβ·(Px − P0) + ρ·ΔT_env·(Px − P0),   tanβ = Σ k_i·ΔT_i
//
// per axis and per direction of approach. The method (docs/model-file.md "How
// the fit works" says the same with the reasons):
//   1. Cold state → Er(x) per direction: mean of the repeated runs at each
//      target, then a polynomial (degree by SelectPolynomialDegree) or the
//      seed-002 table of the means.
//   2. Every other state: residual r = measured − Er(x) point by point.
//      Px = the common pivot of the residual lines r_s(x) = a_s + b_s·x of the
//      states (least squares: Px = −Σ a_s b_s / Σ b_s²), unless given.
//   3. Gains: r = Σ_i k_i·ΔT_i·(Px − x) (+ ρ·ΔT_env·(Px − x)) by least squares over
//      every point of the off-coolant heated/ambient states, with each point's
//      own temperatures (the seed's two-stage "slope per state, then slope vs
//      temperature" is the special case of temperatures constant within a
//      state; the per-state slopes are still reported).
//   4. Key sensors: forward stepwise, adding the candidate that most lowers the
//      leave-one-state-out CV RMS, while it lowers it by ≥ min_cv_improvement,
//      skipping candidates collinear with a chosen one, never more keys than
//      states − 1.
//   5. Coolant: per coolant state, the same keys refitted on that coolant's
//      states (≥ keys + 1 states), else the off-coolant gains times one fitted
//      factor (documented fallback).
#include <array>
#include <optional>
#include <vector>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/modelfit/fit_input.hpp"
#include "trueaxis/modelfit/fit_options.hpp"
#include "trueaxis/modelfit/fit_summary.hpp"

namespace trueaxis::model {

struct FitResult {
  CompositeModel model;  // sources filled from the states; revision/lineage left to the caller
  FitSummary summary;    // also stored in model.fit_summary
};

// Throws InputError (file, line, field) for input that cannot give a sound
// model, std::invalid_argument for invalid options.
FitResult FitCompositeModel(const std::vector<FitState>& states, const FitOptions& options);

// The key-sensor temperatures of one measurement point in the order of
// axis.key_sensors (NaN where the file lacks the sensor) and its ambient.
struct PointTemperatures {
  std::vector<double> key_temp_c;
  double ambient_c = kNaN;
  // The motion-heat input (m/min, motion_heat.hpp) for a model with one: from the history's travel
  // (LaggedKeyTemperatures); NaN when not known (Predict then gives the geometric part only).
  double motion_m_per_min = 0;
};
PointTemperatures TemperaturesForPoint(const AxisModel& axis, const measure::Measurement& m,
                                       const measure::MeasurementPoint& p);

// The readings of sensor `sensor_index` of `m` at each point (file order) passed through the
// first-order lag LagStep(τ = tau_s) in time order (time_s). With a `history` (the logged
// temperatures before the measurement, FitState::history) the filter runs through it first;
// without, it starts at the file's first reading. Points without time_s get no lag.
// tau_s <= 0: the raw readings.
std::vector<double> LaggedSensorSeries(const measure::Measurement& m, std::size_t sensor_index, double tau_s,
                                       const TemperatureHistory* history = nullptr);
// How one key sensor's effective temperature moves (thermal_state.hpp's ObserverStep): its lag,
// the loss time constant per coolant state (0: none) towards its sink, the baseline + the room's
// change when `ambient_index` (m's ambient sensor) and `ambient_baseline_c` are given, else the
// baseline; `coolant` the measurement's own coolant state (the history's rows carry theirs).
struct KeySeriesDynamics {
  double tau_lag_s = 0;
  double fall_factor = 1;  // τ × this while the reading is below the state and no loss runs
  std::array<double, kCoolantStateCount> tau_loss_s{};
  double baseline_c = kNaN;
  double ambient_baseline_c = kNaN;
  std::optional<std::size_t> ambient_index;
  CoolantState coolant = CoolantState::kOff;
};
// The readings of sensor `sensor_index` of `m` at each point (file order) through those dynamics
// in time order, after the `history` when given (as LaggedSensorSeries, which is its loss-free case).
std::vector<double> ObservedSensorSeries(const measure::Measurement& m, std::size_t sensor_index,
                                         const KeySeriesDynamics& dynamics, const TemperatureHistory* history = nullptr);
// TemperaturesForPoint for every point, the key sensors through the model's thermal state
// (axis.key_lag_s, axis.key_loss_s for `coolant`, the file's coolant state) along the file's time
// series: what Predict() is fed for a measurement (predict --measurement, fit summary).
std::vector<PointTemperatures> LaggedKeyTemperatures(const AxisModel& axis, const measure::Measurement& m,
                                                     const TemperatureHistory* history = nullptr,
                                                     CoolantState coolant = CoolantState::kOff);

// measured − predicted, point by point (same runs, directions, targets): the
// error that would remain after compensation with `axis`. Deviation replaced,
// everything else kept, so it can be evaluated by ISO 230-2 directly.
measure::Measurement PredictionResidual(const AxisModel& axis, const measure::Measurement& m, CoolantState coolant,
                                        const TemperatureHistory* history = nullptr);
// The model's prediction for each point (deviation_um = predicted error).
measure::Measurement PredictedMeasurement(const AxisModel& axis, const measure::Measurement& m, CoolantState coolant,
                                          const TemperatureHistory* history = nullptr);

}  // namespace trueaxis::model
