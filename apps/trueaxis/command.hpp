#pragma once
// Subcommand registry of the `trueaxis` program: one file per subcommand,
// each registering itself with a static CommandRegistrar, so adding a
// subcommand never edits main.cpp.
//
//   static void Setup(CLI::App& app) {
//     auto* cmd = app.add_subcommand("analyze", "Evaluate a positioning test");
//     ... cmd->callback([opts] { return RunAnalyze(*opts); });  // returns exit code via throw CLI::RuntimeError
//   }
//   static trueaxis::cli::CommandRegistrar reg("analyze", Setup);
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {

using SetupFn = std::function<void(CLI::App&)>;

struct CommandEntry {
  std::string name;
  SetupFn setup;
};

std::vector<CommandEntry>& Registry();

struct CommandRegistrar {
  CommandRegistrar(std::string name, SetupFn setup) { Registry().push_back({std::move(name), std::move(setup)}); }
};

// The parent subcommand `name` (`sim`, `pitch`, `campaign`, …) whose children attach from their own
// files: whichever setup runs first creates it, the others get the same one.
inline CLI::App* CommandGroup(CLI::App& app, const std::string& name, const std::string& description) {
  for (CLI::App* sub : app.get_subcommands([&](CLI::App* s) { return s->get_name() == name; })) return sub;
  CLI::App* group = app.add_subcommand(name, description);
  group->require_subcommand(1);
  return group;
}

// Exit codes shared by all subcommands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;   // InputError: file/line/field named on stderr
inline constexpr int kExitFailure = 1;    // anything else

// A number of seconds given on the command line (--duration-s, --status-interval-s, …): a
// finite value >= 0, else InputError("command line", 0, option, …) — exit 2. A negative or NaN
// --duration-s meant "run forever" in some commands and "stop at once" in others. What 0
// means stays the command's own (`zero_means`, said in the message: "until stopped", "none").
inline void CheckSecondsOption(double seconds, const std::string& option, const std::string& zero_means) {
  if (!std::isfinite(seconds) || seconds < 0)
    throw InputError("command line", 0, option,
                     fmt::format("'{}' is not a number of seconds >= 0 (0 = {})", seconds, zero_means));
}

}  // namespace trueaxis::cli
