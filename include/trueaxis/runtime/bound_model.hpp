#pragma once
// BoundModel: a CompositeModel resolved against one installation — the CNC
// link's axis names (with their AxisInterface) and the temperature source's
// channel names — so the real-time cycle only follows indices.
//
// Binding happens off the real-time thread (it allocates and may throw);
// the cycle then reads the BoundModel without allocating.
//
// Sensor mapping: a model sensor name (key sensor or ambient) is looked up in
// `channel_map` (model name → channel name); if absent, the channel with the
// same name is used. A model sensor with no channel is a configuration error
// (InputError naming the model file, the axis and the sensor).
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/runtime/axis_interface.hpp"

namespace trueaxis::runtime {

inline constexpr std::size_t kMaxKeySensors = 16;
// Fallback models per axis: at most what a model file may hold (the reader refuses more).
inline constexpr std::size_t kMaxFallbackModels = model::AxisModel::kMaxFallbacks;

struct BoundAxis {
  bool has_model = false;           // false: the model has no entry for this CNC axis → correction 0
  model::AxisModel model;           // copy, with Px overridden by the AxisInterface if set
  std::vector<int> key_channel;     // per model key sensor: channel index
  int ambient_channel = -1;         // -1: no ambient adjustment
  bool thermal_dynamics = false;    // model::HasThermalDynamics(model): else the key state is the readings
  // The model's fallbacks (reduced key sets), bound the same way, in order of preference
  // (`model.fallbacks` itself is emptied, the copies live here).
  std::vector<BoundAxis> fallbacks;
  // Or a model behind the generic interface (PublishAxisModels), with a channel per Sensors().
  std::shared_ptr<const model::AxisErrorModel> generic;
  std::vector<int> generic_channel;
  bool generic_dynamics = false;    // generic->HasDynamics(): advanced by AdvanceModelDynamics
};

struct BoundModel {
  std::shared_ptr<const model::CompositeModel> source;
  std::string label;                // e.g. file path, for logs
  std::uint64_t id = 0;             // increases with every bind of one Compensator
  std::vector<BoundAxis> axes;      // parallel to the CNC link's axes
};

// Binds models behind the generic interface, one per CNC axis at most (matched by Axis()); axes
// without one get no model. Throws InputError(label, ...) on a sensor that maps to no channel,
// more than kMaxKeySensors sensors, or two models for one axis.
std::unique_ptr<BoundModel> BindAxisModels(std::vector<std::shared_ptr<const model::AxisErrorModel>> models,
                                           const std::string& label, const std::vector<AxisInterface>& axes,
                                           const std::vector<std::string>& channel_names,
                                           const std::map<std::string, std::string>& channel_map);

// Throws InputError(label, ...) on a sensor that maps to no channel, or more
// than kMaxKeySensors key sensors.
std::unique_ptr<BoundModel> BindModel(std::shared_ptr<const model::CompositeModel> model, const std::string& label,
                                      const std::vector<AxisInterface>& axes,
                                      const std::vector<std::string>& channel_names,
                                      const std::map<std::string, std::string>& channel_map);

}  // namespace trueaxis::runtime
