#pragma once
// Whole-file read/write with InputError on failure (names the path and why).
#include <string>
#include <string_view>

namespace trueaxis {

// Reads a text file as UTF-8: a UTF-16 file (with a byte-order mark, or UTF-16LE without one, as
// Excel's "Unicode text" saves it) is converted, CR-only line ends become LF; a ZIP container
// (.xlsx) or other binary content is refused naming the cause (InputError).
std::string ReadTextFile(const std::string& path);
// The file's bytes exactly as stored (hashes of sources are of these).
std::string ReadFileBytes(const std::string& path);
// The same decoding for bytes already in memory (`path` names them in errors).
std::string DecodeText(std::string bytes, const std::string& path);
// Writes atomically: to "<path>.tmp" then rename, so a crash never leaves a
// half-written file where a good one stood.
void WriteTextFile(const std::string& path, std::string_view content);

}  // namespace trueaxis
