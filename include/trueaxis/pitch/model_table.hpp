#pragma once
// A pitch table into the model file `run` loads (docs/pitch-error-file.md,
// "Into the model"): the axis's geometric part Er(x), both directions (and
// its fallback models'), becomes the table (kind "table", errors in µm as
// the table holds them), and the axis records the range the table vouches
// for (AxisModel::measured_range_mm). Beyond that range the compensator holds
// the end value and raises outside_measured_range; the thermal part is kept.
#include <string>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/pitch/error_table.hpp"

namespace trueaxis::pitch {

// Replaces axis `table.axis`'s geometric part in `model`. InputError(model_source, "axis") when the
// model has no such axis. A table without its measured range vouches for its own ends.
void PutTableIntoModel(const PitchErrorTable& table, model::CompositeModel& model, const std::string& model_source);

}  // namespace trueaxis::pitch
