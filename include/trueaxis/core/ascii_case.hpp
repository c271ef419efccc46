#pragma once
// ASCII lower case (axis and sensor names: "X" → "x" in x_nut, x_travel_mm); other bytes unchanged.
#include <string>
#include <string_view>

namespace trueaxis {

inline std::string LowerAscii(std::string_view s) {
  std::string out(s);
  for (auto& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}

}  // namespace trueaxis
