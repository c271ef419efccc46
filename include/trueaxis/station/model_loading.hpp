#pragma once
// The model a run configuration names, loaded and handed to the compensator: the seed-000
// composite model (`trueaxis fit`), or a data-driven thermal model (`trueaxis thermal fit`: mlr,
// ridge, pso-bp, hysteresis) deployed on the axes [model] thermal_channels names, through
// thermal::ThermalAxisModel. Used at start and on every reload (docs/runtime.md).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "trueaxis/model/axis_error_model.hpp"
#include "trueaxis/model/composite_model.hpp"

#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/station/installation_config.hpp"

namespace trueaxis::station {

// A model as the compensator runs it: the seed-000 composite model, or per-axis models (a
// data-driven thermal model deployed on the axes of [model] thermal_channels). Kept by the web
// front end so an earlier one can be published again (PublishTo).
struct PublishedModel {
  std::string revision;  // to record: "3"; "ridge" for a thermal model, which has no revision number of its own
  std::shared_ptr<const model::CompositeModel> composite;  // the seed-000 model; null for a thermal model
  std::vector<std::shared_ptr<const model::AxisErrorModel>> axis_models;  // when composite is null
};

// Hands `model` to the compensator (it binds it and ramps to it); throws as PublishModel does.
void PublishTo(runtime::Compensator& compensator, const PublishedModel& model, const std::string& label);

// Why `model` does not belong on the machine named `machine_name` with these axes — fitted on a
// machine of another name (a lathe's model on a VMC compensated with the wrong curve, silently),
// or naming an axis the machine lacks — or nullopt when it fits. A model or machine without a
// name is not compared (docs/model-file.md: a file without `# machine:` is taken as the others').
std::optional<std::string> ModelMachineMismatch(const model::CompositeModel& model, const std::string& machine_name,
                                                const std::vector<std::string>& machine_axes);

// Reads `model_file` as a model of this configuration (composite, or thermal on its
// thermal_channels) and checks it against the machine and the compensator's axes and channels,
// without publishing it: InputError naming the config's [model] file line (when `model_file` is the
// config's) or the file.
PublishedModel ReadModelFor(const runtime::Compensator& compensator, const InstallationConfig& config,
                            const std::string& machine_name, const std::string& model_file);

// Throws InputError naming the file (or the config — its [model] file line — for a model of
// another machine or an axis/channel mismatch); the running model stays in force when it throws.
// `machine_name`: station::Machine::name.
PublishedModel PublishModelFile(runtime::Compensator& compensator, const InstallationConfig& config,
                                const std::string& machine_name);

}  // namespace trueaxis::station
