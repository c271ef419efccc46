#pragma once
// JSON form of CompositeModel (docs/model-file.md). Readers validate every
// field and throw InputError(file, 0, "<json path>", why) on bad input, e.g.
// field 'axes[0].forward.geometric.table_position_mm' "must be ascending".
#include <string>

#include <nlohmann/json.hpp>

#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::model {

nlohmann::json ModelToJson(const CompositeModel& model);
CompositeModel ModelFromJson(const nlohmann::json& doc, const std::string& source);

CompositeModel ReadModelFile(const std::string& path);
void WriteModelFile(const CompositeModel& model, const std::string& path);

}  // namespace trueaxis::model
