#pragma once
// Number <-> text helpers used by every reader and writer.
//
// FormatShortest writes the shortest text that parses back to exactly the
// same double (std::to_chars), so files written by trueaxis round-trip
// losslessly. ParseDouble/ParseInt accept the whole field or nothing
// (surrounding blanks allowed), never a prefix such as "12abc".
#include <optional>
#include <string>
#include <string_view>

namespace trueaxis {

std::string FormatShortest(double value);
std::optional<double> ParseDouble(std::string_view text);
std::optional<long long> ParseInt(std::string_view text);
std::string_view Trim(std::string_view text);

}  // namespace trueaxis
