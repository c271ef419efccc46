#pragma once
// A span of time as a user reads it: "1 d 02:30" (days, hours:minutes), "14:05 h", "3 min 20 s",
// "12.5 s". Never a clock offset: the text says how long, not when.
#include <string>

namespace trueaxis {

// `seconds` >= 0 (a negative or non-finite value gives "—").
std::string FormatDuration(double seconds);

}  // namespace trueaxis
