#include "trueaxis/core/input_error.hpp"

namespace trueaxis {
namespace {
std::string Format(const std::string& source, int line, const std::string& field,
                   const std::string& message) {
  std::string text = source.empty() ? "<input>" : source;
  if (line > 0) text += ":" + std::to_string(line);
  text += ": ";
  if (!field.empty()) text += "field '" + field + "': ";
  text += message;
  return text;
}
}  // namespace

InputError::InputError(std::string source, int line, std::string field, std::string message)
    : std::runtime_error(Format(source, line, field, message)),
      source_(std::move(source)),
      line_(line),
      field_(std::move(field)),
      message_(std::move(message)) {}

InputError::InputError(std::string source, std::string message)
    : InputError(std::move(source), 0, "", std::move(message)) {}

}  // namespace trueaxis
