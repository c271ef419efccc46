#pragma once
// Direction of approach / servo direction of an axis.
//
// kForward is motion towards increasing machine coordinate ('+' in files,
// ISO 230-2's "↑"), kReverse towards decreasing coordinate ('-', "↓").
#include <optional>
#include <string_view>

namespace trueaxis {

enum class Direction { kForward, kReverse };

inline constexpr char DirectionSymbol(Direction d) { return d == Direction::kForward ? '+' : '-'; }
inline constexpr int DirectionSign(Direction d) { return d == Direction::kForward ? 1 : -1; }
inline constexpr std::size_t DirectionIndex(Direction d) { return d == Direction::kForward ? 0 : 1; }

// Parses "+", "-", "fwd"/"forward"/"up", "bwd"/"reverse"/"down" (case-insensitive).
std::optional<Direction> ParseDirection(std::string_view text);

}  // namespace trueaxis
