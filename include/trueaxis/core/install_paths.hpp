#pragma once
// Where trueaxis finds its own files (the web pages, the examples) at run time, so that an installed
// program works wherever it was installed to (docs/install.md):
//   1. <folder of the running program>/../share/trueaxis/<name>   (found through /proc/self/exe: an
//      install under any prefix, a .deb under /usr, a copied prefix);
//   2. the source tree's folder, only when the running program lies inside the build tree it was
//      built in (a developer running build/apps/trueaxis/trueaxis).
// Nothing else is compiled in: a lone copied binary finds nothing and says where it looked.
#include <filesystem>
#include <string>
#include <vector>

namespace trueaxis {

// The folder of the running program (/proc/self/exe, symlinks resolved); empty when unknown.
std::filesystem::path ExecutableDir();

struct DataFolder {
  std::filesystem::path path;                      // empty: not found
  std::vector<std::filesystem::path> looked_in;    // every place tried, in order
  bool found() const { return !path.empty(); }
  std::string LookedIn() const;                    // "A, B" (for an error message)
};

// One of trueaxis's shared folders: `installed_name` under share/trueaxis ("web", "examples"), or
// `source_relative` in the source tree ("src/web/static", "examples") when running from the build tree.
DataFolder FindDataFolder(const std::string& installed_name, const std::string& source_relative);

// The default of an option naming an example file (`machines/vmc850.toml`): examples/<relative> in
// the working folder when it exists there (a checkout), else the same file in the examples folder
// FindDataFolder finds; else examples/<relative> as given (the reader's error then names it).
std::string DefaultExampleFile(const std::string& relative);

}  // namespace trueaxis
