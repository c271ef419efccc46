#include "trueaxis/runtime/bound_model.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/thermal_state.hpp"

namespace trueaxis::runtime {
namespace {

int FindChannel(const std::string& sensor, const std::vector<std::string>& channel_names,
                const std::map<std::string, std::string>& channel_map) {
  auto it = channel_map.find(sensor);
  const std::string& wanted = it == channel_map.end() ? sensor : it->second;
  auto pos = std::find(channel_names.begin(), channel_names.end(), wanted);
  return pos == channel_names.end() ? -1 : static_cast<int>(pos - channel_names.begin());
}

std::string Known(const std::vector<std::string>& names) {
  return names.empty() ? "(none)" : fmt::format("{}", fmt::join(names, ", "));
}

// One keyed axis model (or one of its fallbacks) against the channels.
void BindAxis(const model::AxisModel& am, const AxisInterface& ai, const std::string& label,
              const std::vector<std::string>& channel_names, const std::map<std::string, std::string>& channel_map,
              int fallback_index, BoundAxis& b) {
  b.has_model = true;
  b.model = am;
  b.model.fallbacks.clear();
  if (!std::isnan(ai.reference_position_mm)) b.model.reference_position_mm = ai.reference_position_mm;
  b.thermal_dynamics = model::HasThermalDynamics(b.model);
  const std::string where =
      fmt::format("axes[{}]{}", am.axis, fallback_index >= 0 ? fmt::format(".fallbacks[{}]", fallback_index) : "");
  const std::string field = where + ".key_sensors";
  if (am.key_sensors.size() > kMaxKeySensors)
    throw InputError(label, 0, field, fmt::format("{} key sensors, at most {} supported", am.key_sensors.size(), kMaxKeySensors));
  if (am.baseline_temp_c.size() < am.key_sensors.size())
    throw InputError(label, 0, where + ".baseline_temp_c",
                     fmt::format("{} baselines for {} key sensors", am.baseline_temp_c.size(), am.key_sensors.size()));
  // A sensor the model computes with must read: a model with a thermal part is never run as a
  // geometric-only one for want of a channel. The message says which axis needs it and how to map it.
  const auto unmapped = [&](const std::string& sensor, const std::string& role) {
    return fmt::format("axis {}'s model{} needs the {} '{}', which maps to no temperature channel (channels: {}); "
                       "name the channel that reads it in the run config: [channels] {} = \"CHANNEL\" (one of [machine] channels)",
                       am.axis, fallback_index >= 0 ? fmt::format(" (fallback {})", fallback_index) : "", role, sensor,
                       Known(channel_names), sensor);
  };
  for (const auto& sensor : am.key_sensors) {
    const int ch = FindChannel(sensor, channel_names, channel_map);
    if (ch < 0)
      throw InputError(label, 0, field,
                       unmapped(sensor, "key sensor") +
                           (fallback_index >= 0 ? ", or refit with `trueaxis fit --no-fallback-models`" : ""));
    b.key_channel.push_back(ch);
  }
  // The room sensor only where it changes the prediction (AmbientInUse): a geometric-only model that
  // merely records the room sensor of its measurement runs on a machine without temperature channels.
  if (am.AmbientInUse()) {
    b.ambient_channel = FindChannel(am.ambient_sensor, channel_names, channel_map);
    if (b.ambient_channel < 0)
      throw InputError(label, 0, where + ".ambient_sensor",
                       unmapped(am.ambient_sensor, fmt::format("room (ambient) sensor{}",
                                                               am.rho_um_per_mm_per_c != 0
                                                                   ? fmt::format(" of its ρ term ({} µm/mm/°C)",
                                                                                 am.rho_um_per_mm_per_c)
                                                                   : std::string())) +
                           ", or fit the model without the room term (`trueaxis fit --ambient-sensor none`)");
  }
}

}  // namespace

std::unique_ptr<BoundModel> BindModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label,
                                      const std::vector<AxisInterface>& axes,
                                      const std::vector<std::string>& channel_names,
                                      const std::map<std::string, std::string>& channel_map) {
  if (!model) throw InputError(label, "no model");
  auto bound = std::make_unique<BoundModel>();
  bound->source = model;
  bound->label = label;
  bound->axes.resize(axes.size());
  for (std::size_t i = 0; i < axes.size(); ++i) {
    const model::AxisModel* am = model->FindAxis(axes[i].axis);
    if (!am) continue;
    BoundAxis& b = bound->axes[i];
    BindAxis(*am, axes[i], label, channel_names, channel_map, -1, b);
    if (am->fallbacks.size() > kMaxFallbackModels)  // the model reader refuses such a file; a hand-made model too
      throw InputError(label, 0, fmt::format("axes[{}].fallbacks", am->axis),
                       fmt::format("{} fallback models, at most {} supported", am->fallbacks.size(), kMaxFallbackModels));
    for (std::size_t f = 0; f < am->fallbacks.size(); ++f) {
      b.fallbacks.emplace_back();
      BindAxis(am->fallbacks[f], axes[i], label, channel_names, channel_map, static_cast<int>(f), b.fallbacks.back());
    }
  }
  return bound;
}

std::unique_ptr<BoundModel> BindAxisModels(std::vector<std::shared_ptr<const model::AxisErrorModel>> models,
                                           const std::string& label, const std::vector<AxisInterface>& axes,
                                           const std::vector<std::string>& channel_names,
                                           const std::map<std::string, std::string>& channel_map) {
  auto bound = std::make_unique<BoundModel>();
  bound->label = label;
  bound->axes.resize(axes.size());
  for (auto& m : models) {
    if (!m) throw InputError(label, "no model");
    auto it = std::find_if(axes.begin(), axes.end(), [&](const AxisInterface& a) { return a.axis == m->Axis(); });
    if (it == axes.end())
      throw InputError(label, 0, "axis", fmt::format("the machine has no axis '{}'", m->Axis()));
    BoundAxis& b = bound->axes[static_cast<std::size_t>(it - axes.begin())];
    if (b.has_model) throw InputError(label, 0, "axis", fmt::format("two models for axis '{}'", m->Axis()));
    if (m->Sensors().size() > kMaxKeySensors)
      throw InputError(label, 0, "sensors", fmt::format("{} sensors, at most {} supported", m->Sensors().size(), kMaxKeySensors));
    for (const auto& sensor : m->Sensors()) {
      const int ch = FindChannel(sensor, channel_names, channel_map);
      if (ch < 0)
        throw InputError(label, 0, fmt::format("{}.sensors", m->Axis()),
                         fmt::format("sensor '{}' maps to no temperature channel (channels: {}; map it with [channels] in the run config)",
                                     sensor, Known(channel_names)));
      b.generic_channel.push_back(ch);
    }
    b.has_model = true;
    b.model.axis = m->Axis();
    b.generic_dynamics = m->HasDynamics();
    b.generic = std::move(m);
  }
  return bound;
}

}  // namespace trueaxis::runtime
