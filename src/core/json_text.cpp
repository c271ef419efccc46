#include "trueaxis/core/json_text.hpp"

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {

nlohmann::json ParseJsonOrThrow(std::string_view text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    int line = 1;  // e.byte is the offset of the error: name its line
    for (std::size_t i = 0; i < e.byte && i < text.size(); ++i)
      if (text[i] == '\n') ++line;
    throw InputError(source, line, "", std::string("not valid JSON: ") + e.what());
  }
}

}  // namespace trueaxis
