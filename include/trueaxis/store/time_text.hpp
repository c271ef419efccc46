#pragma once
// Time stamps of the history database: seconds since the Unix epoch (UTC) as
// a double. Users type either that number or an ISO 8601 UTC time.
#include <optional>
#include <string>
#include <string_view>

namespace trueaxis::store {

// "2026-11-22T18:45:07.250Z" (milliseconds, always UTC).
std::string FormatUtc(double time_s);
// Accepts a number of seconds ("1795459507.25", "-3", "0"), or ISO 8601 UTC:
// "2026-11-22", "2026-11-22T18:45", "2026-11-22T18:45:07", "2026-11-22 18:45:07.5Z",
// or with a zone offset: "2026-11-23T02:45:07+08:00" (the same instant as 18:45:07Z).
std::optional<double> ParseTimeText(std::string_view text);

}  // namespace trueaxis::store
