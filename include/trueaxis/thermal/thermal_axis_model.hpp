#pragma once
// Deploys a data-driven thermal error model (MLR/ridge, the seed-003 PSO-BP
// network) on one axis of the real-time compensator: the adapter from
// thermal::ThermalErrorModel to model::AxisErrorModel, which
// runtime::Compensator::PublishAxisModels binds. One of the model's error
// channels is the axis's error; its input sensors are the temperature channels
// the compensator feeds it (by name, through the run config's [channels] map).
//
// Lagged inputs ("t4@lag1800s", thermal/lagged_inputs.hpp) are computed by the adapter from
// their sensor, cycle by cycle, with the fit's own first-order lag (model::LagStep) in the step's
// per-axis model dynamics, so Sensors() lists only real temperature channels. The seed-001
// hysteresis model deploys too: its heating / steady / cooling
// interval comes from the trend of its reference temperature, kept in the step's
// per-axis model dynamics (model::AxisModelDynamics, a model::TrendWindow over the
// classifier's window) and classified by the same rule as the fit
// (thermal::ClassifyTrend); until half a window of history exists — at start, after a
// lost sensor, after a model change — it predicts with its all-data model (start-up).
#include <memory>
#include <string>

#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/thermal/hysteresis_model.hpp"
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
  // The temperature channels the model reads: its inputs' sensors (a lagged input's base sensor),
  // each once, and any reference sensor of the interval rule.
  const std::vector<std::string>& Sensors() const override { return sensors_; }
  std::string Describe() const override;
  // Allocation-free: the model's Predict into a buffer on the stack.
  double ErrorUm(double position_mm, Direction direction, std::span<const double> sensors_c, CoolantState coolant,
                 const model::AxisModelDynamics& dynamics) const override;
  bool HasDynamics() const override { return classifier_.window_s > 0 || lagged_; }
  void Advance(model::AxisModelDynamics& dynamics, double now_s, std::span<const double> sensors_c) const override;
  void ResetDynamics(model::AxisModelDynamics& dynamics) const override;
  // The interval the model predicts with, for these dynamics (kSteady for models without intervals).
  ThermalInterval Interval(const model::AxisModelDynamics& dynamics) const;

 private:
  std::shared_ptr<const ThermalErrorModel> model_;
  std::string axis_;
  std::string channel_;
  // One value the model reads: a sensor (index into sensors_), through a lag of tau_s (0: raw).
  struct Input {
    std::size_t sensor = 0;
    double tau_s = 0;
  };
  std::size_t AddInput(const std::string& name, const std::string& source);
  // The values of inputs_ for these sensors and dynamics (lags not started yet: the readings).
  void Values(std::span<const double> sensors_c, const model::AxisModelDynamics& d, double* out) const;

  std::size_t index_ = 0;
  std::vector<std::string> sensors_;
  std::vector<Input> inputs_;                 // the model's InputSensors(), then reference-only entries
  std::size_t model_inputs_ = 0;              // = InputSensors().size()
  bool lagged_ = false;
  std::vector<std::size_t> reference_index_;  // into inputs_
  IntervalClassifierOptions classifier_{0.0, 0.0};  // window 0: no interval
};

}  // namespace trueaxis::thermal
