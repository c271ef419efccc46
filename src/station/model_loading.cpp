#include "trueaxis/station/model_loading.hpp"

#include <memory>
#include <vector>

#include "trueaxis/model/model_json.hpp"
#include "trueaxis/thermal/thermal_axis_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::station {

PublishedModel PublishModelFile(runtime::Compensator& comp, const runtime::RunConfig& c) {
  if (c.thermal_channels.empty()) {
    auto composite = std::make_shared<const model::CompositeModel>(model::ReadModelFile(c.model_file));
    comp.PublishModel(composite, c.model_file);
    return {std::to_string(composite->revision), composite};
  }
  std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::ReadThermalModelFile(c.model_file);
  std::vector<std::shared_ptr<const model::AxisErrorModel>> axes;
  for (const auto& [axis, channel] : c.thermal_channels)
    axes.push_back(std::make_shared<const thermal::ThermalAxisModel>(fitted, channel, axis, c.model_file));
  comp.PublishAxisModels(std::move(axes), c.model_file);
  return {std::string(fitted->Kind()), nullptr};
}

}  // namespace trueaxis::station
