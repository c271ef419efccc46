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
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

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

// Exit codes shared by all subcommands.
inline constexpr int kExitOk = 0;
inline constexpr int kExitBadInput = 2;   // InputError: file/line/field named on stderr
inline constexpr int kExitFailure = 1;    // anything else

}  // namespace trueaxis::cli
