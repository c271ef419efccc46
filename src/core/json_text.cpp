#include "trueaxis/core/json_text.hpp"

#include <string>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {

nlohmann::json ParseJsonOrThrow(std::string_view text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    int line = 1;  // e.byte is the offset of the error: name its line (and its column below)
    std::size_t line_start = 0;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i)
      if (text[i] == '\n') ++line, line_start = i + 1;
    // nlohmann's text is "[json.exception.parse_error.101] parse error at line 1, column 52: syntax
    // error …": the library's tag and its own position go; the reason stays.
    std::string why = e.what();
    if (const auto colon = why.find(": "); why.rfind("[json.exception", 0) == 0 && colon != std::string::npos)
      why = why.substr(colon + 2);
    const std::size_t column = e.byte > line_start ? e.byte - line_start : 1;
    throw InputError(source, line, "", "not valid JSON (column " + std::to_string(column) + "): " + why);
  }
}

}  // namespace trueaxis
