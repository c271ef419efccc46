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
// Writes atomically: to TemporaryPathFor(path) then CommitTemporaryFile, so a crash never leaves a
// half-written file where a good one stood.
void WriteTextFile(const std::string& path, std::string_view content);

// An atomic write in two steps, for writers that stream (exports, workbooks):
//  - TemporaryPathFor(path): the file to fill first — "<file>.tmp" next to the file (next to a
//    symlink's target, so the rename stays on one file system and the link stays a link), or in the
//    system's temporary directory when `path` is a device, FIFO or socket (/dev/null, /dev/stdout).
//    A directory is an InputError.
//  - CommitTemporaryFile(tmp, path): renames tmp over the file (or the link's target); into a device
//    it copies the bytes instead, since renaming a file over /dev/null would replace the device (as
//    root it did). tmp is gone afterwards; InputError naming `path` on failure.
std::string TemporaryPathFor(const std::string& path);
void CommitTemporaryFile(const std::string& tmp, const std::string& path);

}  // namespace trueaxis
