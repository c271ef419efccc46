#include "trueaxis/core/install_paths.hpp"

#include <system_error>

// Set by src/core/CMakeLists.txt: the tree this program was built in and its sources.
#ifndef TRUEAXIS_BUILD_TREE_DIR
#define TRUEAXIS_BUILD_TREE_DIR ""
#endif
#ifndef TRUEAXIS_SOURCE_TREE_DIR
#define TRUEAXIS_SOURCE_TREE_DIR ""
#endif

namespace trueaxis {

namespace fs = std::filesystem;

fs::path ExecutableDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty()) return {};
  return exe.parent_path();
}

namespace {

// True when `inside` is `folder` or lies below it (both made canonical as far as they exist).
bool IsWithin(const fs::path& inside, const fs::path& folder) {
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(inside, ec);
  if (ec) return false;
  const fs::path b = fs::weakly_canonical(folder, ec);
  if (ec || b.empty()) return false;
  auto ai = a.begin();
  for (auto bi = b.begin(); bi != b.end(); ++bi, ++ai) {
    if (bi->empty()) continue;  // a trailing separator
    if (ai == a.end() || *ai != *bi) return false;
  }
  return true;
}

}  // namespace

std::string DataFolder::LookedIn() const {
  std::string s;
  for (const auto& p : looked_in) s += (s.empty() ? "" : ", ") + p.string();
  return s.empty() ? "nowhere (the program's own path is unknown)" : s;
}

DataFolder FindDataFolder(const std::string& installed_name, const std::string& source_relative) {
  DataFolder result;
  std::error_code ec;
  const fs::path exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    const fs::path installed = (exe_dir / ".." / "share" / "trueaxis" / installed_name).lexically_normal();
    result.looked_in.push_back(installed);
    if (fs::is_directory(installed, ec)) {
      result.path = installed;
      return result;
    }
  }
  const fs::path build_tree = TRUEAXIS_BUILD_TREE_DIR;
  if (!exe_dir.empty() && !build_tree.empty() && IsWithin(exe_dir, build_tree)) {
    const fs::path source = (fs::path(TRUEAXIS_SOURCE_TREE_DIR) / source_relative).lexically_normal();
    result.looked_in.push_back(source);
    if (fs::is_directory(source, ec)) result.path = source;
  }
  return result;
}

std::string DefaultExampleFile(const std::string& relative) {
  const fs::path in_checkout = fs::path("examples") / relative;
  std::error_code ec;
  if (fs::exists(in_checkout, ec)) return in_checkout.string();
  const DataFolder examples = FindDataFolder("examples", "examples");
  if (examples.found() && fs::exists(examples.path / relative, ec)) return (examples.path / relative).string();
  return in_checkout.string();
}

}  // namespace trueaxis
