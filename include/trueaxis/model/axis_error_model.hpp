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
#include <span>
#include <string>
#include <vector>

#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/direction.hpp"

namespace trueaxis::model {

class AxisErrorModel {
 public:
  virtual ~AxisErrorModel() = default;
  virtual const std::string& Axis() const = 0;                  // CNC axis name it is for
  virtual const std::vector<std::string>& Sensors() const = 0;  // temperature inputs, in order
  virtual std::string Describe() const = 0;                     // one line, for logs
  // Predicted error (actual − commanded, µm) at the model position, approached in `direction`,
  // with `sensors_c` in Sensors() order.
  virtual double ErrorUm(double position_mm, Direction direction, std::span<const double> sensors_c,
                         CoolantState coolant) const = 0;
};

}  // namespace trueaxis::model
