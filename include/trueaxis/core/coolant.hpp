#pragma once
// Coolant working states (seed 000 "动态调整模块": k1, k2 are kept per coolant
// state). The numeric codes are the ones the CNC PMC window reports.
#include <array>
#include <optional>
#include <string_view>

namespace trueaxis {

enum class CoolantState : int { kOff = 0, kFlood = 1, kMist = 2, kAir = 3 };
inline constexpr int kCoolantStateCount = 4;

inline constexpr std::array<std::string_view, kCoolantStateCount> kCoolantStateNames = {
    "off", "flood", "mist", "air"};

inline constexpr std::string_view CoolantStateName(CoolantState s) {
  return kCoolantStateNames[static_cast<int>(s)];
}

inline std::optional<CoolantState> ParseCoolantState(std::string_view name) {
  for (int i = 0; i < kCoolantStateCount; ++i)
    if (kCoolantStateNames[i] == name) return static_cast<CoolantState>(i);
  return std::nullopt;
}

inline std::optional<CoolantState> CoolantStateFromCode(int code) {
  if (code < 0 || code >= kCoolantStateCount) return std::nullopt;
  return static_cast<CoolantState>(code);
}

}  // namespace trueaxis
