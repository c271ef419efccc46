#include "trueaxis/station/model_loading.hpp"

#include <algorithm>
#include <memory>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"

#include "trueaxis/model/model_json.hpp"
#include "trueaxis/runtime/bound_model.hpp"
#include "trueaxis/thermal/thermal_axis_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::station {

void PublishTo(runtime::Compensator& comp, const PublishedModel& m, const std::string& label) {
  if (m.composite)
    comp.PublishModel(m.composite, label);
  else
    comp.PublishAxisModels(m.axis_models, label);
}

std::optional<std::string> ModelMachineMismatch(const model::CompositeModel& m, const std::string& machine_name,
                                                const std::vector<std::string>& machine_axes) {
  if (!m.machine.empty() && !machine_name.empty() && LowerAscii(m.machine) != LowerAscii(machine_name))
    return fmt::format("the model was fitted on machine '{}', this is machine '{}': fit a model on this machine",
                       m.machine, machine_name);
  for (const auto& a : m.axes)
    if (std::find(machine_axes.begin(), machine_axes.end(), a.axis) == machine_axes.end())
      return fmt::format("the model has axis '{}', the machine{} has not (its axes: {})", a.axis,
                         machine_name.empty() ? "" : " '" + machine_name + "'", fmt::join(machine_axes, ", "));
  return std::nullopt;
}

PublishedModel ReadModelFor(const runtime::Compensator& comp, const InstallationConfig& c, const std::string& machine_name,
                            const std::string& model_file) {
  const bool configured = model_file == c.model_file;  // errors of the model a config names point at its line
  if (configured) c.RequireFile("model.file", model_file);
  PublishedModel published;
  if (c.thermal_channels.empty()) {
    std::shared_ptr<const model::CompositeModel> composite = model::ReadSharedModelFile(model_file);
    std::vector<std::string> axes;
    for (const auto& a : comp.axes()) axes.push_back(a.axis);
    if (auto why = ModelMachineMismatch(*composite, machine_name, axes))
      throw InputError(configured ? c.source : model_file, configured ? c.LineOf("model.file") : 0, "model.file",
                       fmt::format("'{}': {}", model_file, *why));
    published = PublishedModel{std::to_string(composite->revision), composite, {}};
    // The binding's own checks (sensors the machine lacks, ...), without publishing.
    runtime::BindModel(composite, model_file, comp.axes(), comp.channel_names(), comp.options().channel_map);
    return published;
  }
  std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::ReadThermalModelFile(model_file);
  std::vector<std::shared_ptr<const model::AxisErrorModel>> axes;
  for (const auto& [axis, channel] : c.thermal_channels)
    axes.push_back(std::make_shared<const thermal::ThermalAxisModel>(fitted, channel, axis, model_file));
  published = PublishedModel{std::string(fitted->Kind()), nullptr, std::move(axes)};
  runtime::BindAxisModels(published.axis_models, model_file, comp.axes(), comp.channel_names(), comp.options().channel_map);
  return published;
}

PublishedModel PublishModelFile(runtime::Compensator& comp, const InstallationConfig& c, const std::string& machine_name) {
  PublishedModel published = ReadModelFor(comp, c, machine_name, c.model_file);
  PublishTo(comp, published, c.model_file);
  return published;
}

}  // namespace trueaxis::station
