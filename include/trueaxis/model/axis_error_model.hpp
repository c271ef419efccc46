#pragma once
// AxisErrorModel: what the real-time compensator binds for one axis when the
// model is not the seed-000 CompositeModel (runtime::Compensator::PublishAxisModels)
// — e.g. a data-driven thermal model (thermal/: MLR/ridge, PSO-BP) through its
// adapter. The compensator maps Sensors() to temperature channels by name (with
// the run config's [channels] map), gathers their conditioned values every
// cycle and applies correction = −ErrorUm (docs/sign-convention.md) through the
// same limiter as every other correction.
//
// Contract: ErrorUm is const, pure and allocation-free (it runs on the real-time
// thread); it is called only when every sensor is usable — a lost sensor makes
// the compensator ramp the axis to zero (alarm sensor_fallback).
//
// A model whose prediction depends on the temperatures' course (the seed-001
// hysteresis model: a sub-model per heating / steady / cooling interval of a
// reference temperature's trend) keeps that course in AxisModelDynamics, which
// the runtime step owns (runtime::ModelDynamics) and advances every cycle through
// Advance(); a lost sensor or a new model restarts it (ResetDynamics). Both are
// allocation-free like ErrorUm.
#include <array>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/direction.hpp"
#include "trueaxis/model/trend_window.hpp"

namespace trueaxis::model {

// What a model behind AxisErrorModel may remember between cycles (fixed size: the step holds one
// per axis): first-order lags of its inputs (a data-driven model's "t4@lag1800s") and the
// trailing-window trend of a reference temperature (the hysteresis model's interval).
struct AxisModelDynamics {
  static constexpr std::size_t kMaxLaggedInputs = 64;
  std::array<double, kMaxLaggedInputs> lagged_c{};
  double time_s = 0;
  bool started = false;  // false: the lags start at the next readings
  TrendWindow trend;
};

class AxisErrorModel {
 public:
  virtual ~AxisErrorModel() = default;
  virtual const std::string& Axis() const = 0;                  // CNC axis name it is for
  virtual const std::vector<std::string>& Sensors() const = 0;  // temperature inputs, in order
  virtual std::string Describe() const = 0;                     // one line, for logs
  // Predicted error (actual − commanded, µm) at the model position, approached in `direction`,
  // with `sensors_c` in Sensors() order.
  virtual double ErrorUm(double position_mm, Direction direction, std::span<const double> sensors_c,
                         CoolantState coolant, const AxisModelDynamics& dynamics) const = 0;

  virtual bool HasDynamics() const { return false; }
  // Every cycle while every sensor is usable, with the sensors in Sensors() order.
  virtual void Advance(AxisModelDynamics& /*dynamics*/, double /*now_s*/, std::span<const double> /*sensors_c*/) const {}
  // At the start, after a lost sensor and when the model changes.
  virtual void ResetDynamics(AxisModelDynamics& /*dynamics*/) const {}
};

}  // namespace trueaxis::model
