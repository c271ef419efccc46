#include "trueaxis/thermal/thermal_axis_model.hpp"

#include <algorithm>
#include <array>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"

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
  if (model_->UsesInterval())
    throw InputError(source, 0, "kind",
                     fmt::format("the {} model needs the heating/cooling interval of the temperature trend, which the "
                                 "real-time compensator does not track yet; deploy an mlr, ridge or pso-bp model",
                                 model_->Kind()));
  index_ = static_cast<std::size_t>(it - channels.begin());
}

std::string ThermalAxisModel::Describe() const {
  return fmt::format("{} thermal model, channel {} on axis {} (sensors {})", model_->Kind(), channel_, axis_,
                     fmt::join(model_->InputSensors(), ", "));
}

double ThermalAxisModel::ErrorUm(double position_mm, Direction, std::span<const double> sensors_c, CoolantState) const {
  std::array<double, kMaxChannels> out{};
  ThermalSample sample{sensors_c, position_mm, ThermalInterval::kSteady};
  model_->Predict(sample, std::span<double>(out.data(), model_->Channels().size()));
  return out[index_];
}

}  // namespace trueaxis::thermal
