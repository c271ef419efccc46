#include "trueaxis/thermal/thermal_axis_model.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/thermal_lag.hpp"
#include "trueaxis/thermal/lagged_inputs.hpp"

namespace trueaxis::thermal {

ThermalAxisModel::ThermalAxisModel(std::shared_ptr<const ThermalErrorModel> model, const std::string& channel,
                                   std::string axis, const std::string& source)
    : model_(std::move(model)), axis_(std::move(axis)), channel_(channel) {
  if (!model_) throw InputError(source, "no model");
  const auto& channels = model_->Channels();
  const auto it = std::find(channels.begin(), channels.end(), channel);
  if (it == channels.end())
    throw InputError(source, 0, "channel",
                     fmt::format("the {} model has no error channel '{}' (it has: {})", model_->Kind(), channel,
                                 fmt::join(channels, ", ")));
  if (channels.size() > kMaxChannels)
    throw InputError(source, 0, "channel", fmt::format("{} error channels, at most {} supported", channels.size(), kMaxChannels));
  index_ = static_cast<std::size_t>(it - channels.begin());
  for (const auto& name : model_->InputSensors()) AddInput(name, source);
  model_inputs_ = inputs_.size();
  if (model_->UsesInterval()) {
    const auto* hysteresis = dynamic_cast<const HysteresisThermalModel*>(model_.get());
    if (!hysteresis)
      throw InputError(source, 0, "kind",
                       fmt::format("the {} model needs an interval the compensator does not know how to track", model_->Kind()));
    classifier_ = hysteresis->classifier();
    const auto& names = model_->InputSensors();
    for (const auto& name : hysteresis->reference_sensors()) {
      const auto r = std::find(names.begin(), names.end(), name);
      reference_index_.push_back(r != names.end() ? static_cast<std::size_t>(r - names.begin()) : AddInput(name, source));
    }
    if (reference_index_.empty())
      throw InputError(source, 0, "reference_sensors", "the hysteresis model names no reference temperature for its interval");
  }
  if (inputs_.size() > model::AxisModelDynamics::kMaxLaggedInputs)
    throw InputError(source, 0, "sensors",
                     fmt::format("{} inputs, at most {} supported", inputs_.size(), model::AxisModelDynamics::kMaxLaggedInputs));
}

std::size_t ThermalAxisModel::AddInput(const std::string& name, const std::string& source) {
  Input in;
  std::string sensor = name;
  if (ParseLaggedName(name, &sensor, &in.tau_s)) {
    if (!(in.tau_s > 0)) throw InputError(source, 0, "sensors", fmt::format("input '{}': the lag must be > 0 s", name));
    lagged_ = true;
  }
  auto s = std::find(sensors_.begin(), sensors_.end(), sensor);
  if (s == sensors_.end()) s = sensors_.insert(sensors_.end(), sensor);
  in.sensor = static_cast<std::size_t>(s - sensors_.begin());
  inputs_.push_back(in);
  return inputs_.size() - 1;
}

std::string ThermalAxisModel::Describe() const {
  return fmt::format("{} thermal model, channel {} on axis {} (sensors {})", model_->Kind(), channel_, axis_,
                     fmt::join(model_->InputSensors(), ", "));
}

void ThermalAxisModel::Values(std::span<const double> sensors_c, const model::AxisModelDynamics& d, double* out) const {
  for (std::size_t j = 0; j < inputs_.size(); ++j)
    out[j] = inputs_[j].tau_s > 0 && d.started ? d.lagged_c[j] : sensors_c[inputs_[j].sensor];
}

ThermalInterval ThermalAxisModel::Interval(const model::AxisModelDynamics& d) const {
  if (!(classifier_.window_s > 0)) return ThermalInterval::kSteady;
  return ClassifyTrend(d.trend.SlopePerH(), d.trend.Samples(), d.trend.SpanS(), classifier_);
}

void ThermalAxisModel::ResetDynamics(model::AxisModelDynamics& d) const {
  d.started = false;
  if (classifier_.window_s > 0) d.trend.Configure(classifier_.window_s);  // fills a fixed array: no allocation
}

void ThermalAxisModel::Advance(model::AxisModelDynamics& d, double now_s, std::span<const double> sensors_c) const {
  // The lags (the fit's own step: model::LagStep); the first readings start them.
  const double dt = d.started ? now_s - d.time_s : 0.0;
  for (std::size_t j = 0; j < inputs_.size(); ++j)
    if (inputs_[j].tau_s > 0)
      d.lagged_c[j] = model::LagStep(d.started ? d.lagged_c[j] : std::nan(""), sensors_c[inputs_[j].sensor], dt, inputs_[j].tau_s);
  d.time_s = now_s;
  d.started = true;
  if (!(classifier_.window_s > 0)) return;
  if (d.trend.window_s() != classifier_.window_s) d.trend.Configure(classifier_.window_s);
  std::array<double, model::AxisModelDynamics::kMaxLaggedInputs> values;
  Values(sensors_c, d, values.data());
  double reference_c = 0;
  for (const std::size_t k : reference_index_) reference_c += values[k];
  d.trend.Push(now_s, reference_c / static_cast<double>(reference_index_.size()));
}

double ThermalAxisModel::ErrorUm(double position_mm, Direction, std::span<const double> sensors_c, CoolantState,
                                 const model::AxisModelDynamics& dynamics) const {
  std::array<double, model::AxisModelDynamics::kMaxLaggedInputs> values;
  Values(sensors_c, dynamics, values.data());
  std::array<double, kMaxChannels> out{};
  ThermalSample sample{std::span<const double>(values.data(), model_inputs_), position_mm, Interval(dynamics)};
  model_->Predict(sample, std::span<double>(out.data(), model_->Channels().size()));
  return out[index_];
}

}  // namespace trueaxis::thermal
