#pragma once
// Whole-file read/write with InputError on failure (names the path and why).
#include <string>
#include <string_view>

namespace trueaxis {

std::string ReadTextFile(const std::string& path);
// Writes atomically: to "<path>.tmp" then rename, so a crash never leaves a
// half-written file where a good one stood.
void WriteTextFile(const std::string& path, std::string_view content);

}  // namespace trueaxis
