#include "trueaxis/station/model_loading.hpp"

#include <memory>
#include <vector>

#include "trueaxis/model/model_json.hpp"
#include "trueaxis/thermal/thermal_axis_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::station {

void PublishTo(runtime::Compensator& comp, const PublishedModel& m, const std::string& label) {
  if (m.composite)
    comp.PublishModel(m.composite, label);
  else
    comp.PublishAxisModels(m.axis_models, label);
}

PublishedModel PublishModelFile(runtime::Compensator& comp, const runtime::RunConfig& c) {
  if (c.thermal_channels.empty()) {
    auto composite = std::make_shared<const model::CompositeModel>(model::ReadModelFile(c.model_file));
    PublishedModel published{std::to_string(composite->revision), composite, {}};
    PublishTo(comp, published, c.model_file);
    return published;
  }
  std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::ReadThermalModelFile(c.model_file);
  std::vector<std::shared_ptr<const model::AxisErrorModel>> axes;
  for (const auto& [axis, channel] : c.thermal_channels)
    axes.push_back(std::make_shared<const thermal::ThermalAxisModel>(fitted, channel, axis, c.model_file));
  PublishedModel published{std::string(fitted->Kind()), nullptr, std::move(axes)};
  PublishTo(comp, published, c.model_file);
  return published;
}

}  // namespace trueaxis::station
