#pragma once
// Deploys a data-driven thermal error model (MLR/ridge, the seed-003 PSO-BP
// network) on one axis of the real-time compensator: the adapter from
// thermal::ThermalErrorModel to model::AxisErrorModel, which
// runtime::Compensator::PublishAxisModels binds. One of the model's error
// channels is the axis's error; its input sensors are the temperature channels
// the compensator feeds it (by name, through the run config's [channels] map).
//
// Not yet deployable: models that use the heating/steady/cooling interval (the
// seed-001 hysteresis model) — the interval needs the temperature trend as
// per-axis state advanced every cycle (runtime::ModelDynamics), which is not
// wired yet; the constructor refuses them with the reason.
#include <memory>
#include <string>

#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::thermal {

class ThermalAxisModel final : public model::AxisErrorModel {
 public:
  static constexpr std::size_t kMaxChannels = 32;
  // `channel`: the model's error channel (Channels()) that is this axis's error. Throws
  // InputError(source, ...) naming the channel or the reason the model cannot be deployed.
  ThermalAxisModel(std::shared_ptr<const ThermalErrorModel> model, const std::string& channel, std::string axis,
                   const std::string& source);

  const std::string& Axis() const override { return axis_; }
  const std::vector<std::string>& Sensors() const override { return model_->InputSensors(); }
  std::string Describe() const override;
  // Allocation-free: the model's Predict into a buffer on the stack.
  double ErrorUm(double position_mm, Direction direction, std::span<const double> sensors_c,
                 CoolantState coolant) const override;

 private:
  std::shared_ptr<const ThermalErrorModel> model_;
  std::string axis_;
  std::string channel_;
  std::size_t index_ = 0;
};

}  // namespace trueaxis::thermal
