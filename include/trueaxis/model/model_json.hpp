#pragma once
// JSON form of CompositeModel (docs/model-file.md). Readers validate every
// field and throw InputError(file, 0, "<json path>", why) on bad input, e.g.
// field 'axes[0].forward.geometric.table_position_mm' "must be ascending".
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::model {

nlohmann::json ModelToJson(const CompositeModel& model);
CompositeModel ModelFromJson(const nlohmann::json& doc, const std::string& source);

CompositeModel ReadModelFile(const std::string& path);
// The same, shared: a file whose bytes are those of a model read before and still in use is not
// parsed again, its model is handed out once more (immutable) — a workshop server's machines that
// load the same model file hold one copy. Thread-safe.
std::shared_ptr<const CompositeModel> ReadSharedModelFile(const std::string& path);
void WriteModelFile(const CompositeModel& model, const std::string& path);

}  // namespace trueaxis::model
