#include "trueaxis/core/output_path.hpp"

#include <filesystem>
#include <system_error>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis {

bool IsSameFile(const std::string& a, const std::string& b) {
  if (a.empty() || b.empty()) return false;
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool a_exists = fs::exists(a, ec);
  const bool b_exists = fs::exists(b, ec);
  if (a_exists && b_exists) {
    const bool same = fs::equivalent(a, b, ec);
    return !ec && same;
  }
  if (a_exists != b_exists) return false;  // one file exists, the other does not: not the same file
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ec), ec);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ec), ec);
  return ca.lexically_normal() == cb.lexically_normal();
}

void RefuseOutputOverInput(const std::string& out_path, const std::vector<std::string>& input_paths,
                           const std::string& option) {
  for (const auto& input : input_paths)
    if (IsSameFile(out_path, input))
      throw InputError("command line", 0, option,
                       fmt::format("'{}' is the input file '{}': writing there would destroy it; give another path",
                                   out_path, input));
}

void RefuseUnwritableOutputFile(const std::string& out_path, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(out_path, ec))
    throw InputError("command line", 0, option, fmt::format("'{}' is a directory; give the file to write", out_path));
  const fs::path parent = fs::path(out_path).parent_path();
  if (!parent.empty() && !fs::is_directory(parent, ec))
    throw InputError("command line", 0, option,
                     fmt::format("'{}': the folder '{}' does not exist", out_path, parent.string()));
}

}  // namespace trueaxis
