#include "trueaxis/core/direction.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace trueaxis {

std::optional<Direction> ParseDirection(std::string_view text) {
  std::string t(text);
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return std::tolower(c); });
  if (t == "+" || t == "fwd" || t == "forward" || t == "up" || t == "pos") return Direction::kForward;
  if (t == "-" || t == "bwd" || t == "reverse" || t == "backward" || t == "down" || t == "neg")
    return Direction::kReverse;
  return std::nullopt;
}

}  // namespace trueaxis
