#pragma once
// Parses a JSON document or throws InputError(source, line, "", "not valid JSON: ...") with the
// line of the error — the one JSON entry point of every reader (model file, campaign manifest,
// calibration file, thermal model file), as ParseTomlOrThrow is for TOML.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace trueaxis {

nlohmann::json ParseJsonOrThrow(std::string_view text, const std::string& source);

}  // namespace trueaxis
