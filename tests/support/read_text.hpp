#pragma once
// A whole text file as a string ("" when it cannot be read), for tests that check a file's content.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace trueaxis::testing {

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace trueaxis::testing
