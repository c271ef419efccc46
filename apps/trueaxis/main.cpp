// trueaxis: measure, model and compensate machine-tool axis errors.
// Subcommands live one per file (cmd_*.cpp) and register themselves.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {
std::vector<CommandEntry>& Registry() {
  static std::vector<CommandEntry> registry;
  return registry;
}
}  // namespace trueaxis::cli

int main(int argc, char** argv) {
  using namespace trueaxis::cli;
  CLI::App app{"trueaxis — measure, model and compensate the geometric and thermal errors of machine-tool axes"};
  app.set_version_flag("--version", "trueaxis " TRUEAXIS_VERSION);  // the project's version (CMakeLists.txt)
  app.require_subcommand(1);
  auto& registry = Registry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (const auto& entry : registry) entry.setup(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    // A command that failed after printing why (not a usage error): its own exit code.
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help) itself; its own exit codes
    // (104–109 …) are folded into ours: help/version is success, any usage
    // error is bad input like a bad file (README: exit code 2).
    const int cli11_code = app.exit(e);
    return cli11_code == 0 ? kExitOk : kExitBadInput;
  } catch (const trueaxis::InputError& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the user gave that cannot be read or created: bad input, said as path: reason.
    fmt::print(stderr, "error: {}: {}\n", e.path1().string(), e.code().message());
    return kExitBadInput;
  } catch (const std::exception& e) {
    fmt::print(stderr, "error: {}\n", e.what());
    return kExitFailure;
  }
  return kExitOk;
}
