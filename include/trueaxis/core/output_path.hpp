#pragma once
// An output file the user names must not be one of the files the command reads: writing it would
// destroy that input (the sweep's B1: `history export --db h.sqlite --out h.sqlite` replaced the
// database with CSV and exited 0; `analyze run.csv --report run.csv` replaced the laser run with HTML).
//
// RefuseOutputOverInput throws InputError("command line", 0, <option>, ...) naming the option and both
// paths when `out_path` is the same file as one of `input_paths`: the same inode when both exist
// (a symlink, a hard link, "./a" and "a"), else the same normalised absolute path. Empty paths are
// ignored (an option not given).
#include <string>
#include <vector>

namespace trueaxis {

bool IsSameFile(const std::string& a, const std::string& b);

void RefuseOutputOverInput(const std::string& out_path, const std::vector<std::string>& input_paths,
                           const std::string& option);

// Throws InputError("command line", 0, <option>, ...) when `out_path` names an existing directory or
// lies in a folder that does not exist, before any work (it failed at the final rename, exit 1).
void RefuseUnwritableOutputFile(const std::string& out_path, const std::string& option);

}  // namespace trueaxis
