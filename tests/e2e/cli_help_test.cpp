// What a new user meets first: `trueaxis --help` grouped by what the commands are for, a mistyped
// command or option answered with the nearest real one, help texts free of development history,
// and docs/cli.md equal to what the program prints.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "../apps/trueaxis/command_groups.hpp"
#include "support/cli_runner.hpp"
#include "support/read_text.hpp"

namespace {

using trueaxis::testing::RunCli;

// The subcommands a CLI11 help text lists: names under every heading but Options and Positionals
// (the same rule as scripts/cli-reference.sh).
std::vector<std::string> ListedSubcommands(const std::string& help) {
  std::vector<std::string> names;
  std::istringstream in(help);
  std::string line;
  bool listing = false;
  const std::regex entry(R"(^  ([a-z0-9][a-z0-9-]*)( |$))");
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != ' ') {
      listing = line.back() == ':' && line != "Options:" && line != "Positionals:";
      continue;
    }
    std::smatch m;
    if (listing && std::regex_search(line, m, entry)) names.push_back(m[1]);
  }
  return names;
}

// Every command path ("sim campaign", …) with its help text, walked from the top.
void Walk(const std::string& path, std::vector<std::pair<std::string, std::string>>& out) {
  const auto r = RunCli(path + (path.empty() ? "" : " ") + "--help");
  ASSERT_EQ(r.exit_code, 0) << "trueaxis " << path << " --help\n" << r.output;
  out.emplace_back(path, r.output);
  for (const auto& sub : ListedSubcommands(r.output)) Walk(path.empty() ? sub : path + " " + sub, out);
}

std::vector<std::pair<std::string, std::string>> AllHelp() {
  std::vector<std::pair<std::string, std::string>> all;
  Walk("", all);
  return all;
}

TEST(CliHelp, TopLevelHelpGroupsCommandsUnderTheHeadingsInOrder) {
  const auto r = RunCli("--help");
  ASSERT_EQ(r.exit_code, 0);
  std::size_t at = 0;
  for (const auto heading : trueaxis::cli::kCommandGroups) {
    const auto found = r.output.find("\n" + std::string(heading) + ":\n", at);
    EXPECT_NE(found, std::string::npos) << "heading '" << heading << "' missing or out of order:\n" << r.output;
    if (found != std::string::npos) at = found;
  }
  EXPECT_EQ(r.output.find("\nSubcommands:\n"), std::string::npos) << "a command without a group:\n" << r.output;
  EXPECT_NE(r.output.find("  analyze"), std::string::npos);
}

// A command added without a place in command_groups.hpp lands under Tools; this names it.
TEST(CliHelp, EveryCommandHasAGroupOfItsOwn) {
  const auto names = ListedSubcommands(RunCli("--help").output);
  ASSERT_GE(names.size(), 15u);
  std::vector<std::string> ungrouped;
  for (const auto& n : names)
    if (!trueaxis::cli::GroupOf(n)) ungrouped.push_back(n);
  std::string list;
  for (const auto& n : ungrouped) list += " " + n;
  EXPECT_TRUE(ungrouped.empty()) << "add these commands to apps/trueaxis/command_groups.hpp:" << list;
}

// `trueaxis args` is a usage error (exit 2) whose message contains `says`; returns the output.
std::string ExpectUsageError(const std::string& args, const std::string& says) {
  const auto r = RunCli(args);
  EXPECT_EQ(r.exit_code, 2) << "trueaxis " << args << "\n" << r.output;
  EXPECT_NE(r.output.find(says), std::string::npos) << "trueaxis " << args << "\n" << r.output;
  return r.output;
}

TEST(CliHelp, AMistypedCommandIsAnsweredWithTheNearestOne) {
  ExpectUsageError("analize x.csv", "unknown command 'analize'; did you mean 'analyze'?");
  ExpectUsageError("sim campain --machine m.toml", "unknown command 'campain' of 'trueaxis sim'; did you mean 'campaign'?");
  const auto far = ExpectUsageError("xyzzy", "unknown command 'xyzzy'");
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << "nothing is near 'xyzzy':\n" << far;
}

TEST(CliHelp, AMistypedOptionIsAnsweredWithTheNearestOne) {
  const std::string run = "run --config " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/run/virtual.toml";
  ExpectUsageError(run + " --status-intervals 1",
                   "unknown option '--status-intervals' for 'trueaxis run'; did you mean '--status-interval-s'?");
  // An option's value that looks like a word is not taken for a command.
  ExpectUsageError("analyze --standard analize --no-such-option x.csv",
                   "unknown option '--no-such-option' for 'trueaxis analyze'");
}

// One name for the status-line interval everywhere; run's earlier --status-s still works, unlisted.
TEST(CliHelp, StatusIntervalHasOneNameAndTheOldSpellingStillWorks) {
  for (const std::string cmd : {"run", "server", "terminal", "sim serve", "sim shop"}) {
    const auto r = RunCli(cmd + " --help");
    EXPECT_NE(r.output.find("--status-interval-s"), std::string::npos) << cmd << "\n" << r.output;
    EXPECT_EQ(r.output.find("--status-s "), std::string::npos) << cmd << "\n" << r.output;
  }
  const std::string run = "run --config " + std::string(TRUEAXIS_SOURCE_DIR) + "/examples/run/virtual.toml";
  const auto old = RunCli(run + " --status-s nan");
  EXPECT_EQ(old.exit_code, 2) << old.output;
  EXPECT_NE(old.output.find("field '--status-interval-s'"), std::string::npos) << old.output;
}

// Users cannot see the project's issue tracker or its work log, nor the source documents by number.
TEST(CliHelp, NoHelpTextSpeaksOfIssuesStopsOrSeedNumbers) {
  const auto all = AllHelp();
  ASSERT_GE(all.size(), 30u);
  const std::regex history(R"(\b(issue|stop|seed)[ -]#?0*[0-9]+\b)", std::regex::icase);
  for (const auto& [path, help] : all) {
    std::smatch m;
    EXPECT_FALSE(std::regex_search(help, m, history)) << "trueaxis " << path << " --help says '" << m.str() << "'";
  }
}

TEST(CliHelp, TheHistoryCheckCatchesWhatItShould) {
  const std::regex history(R"(\b(issue|stop|seed)[ -]#?0*[0-9]+\b)", std::regex::icase);
  EXPECT_TRUE(std::regex_search(std::string("as in issue 10's work"), history));
  EXPECT_TRUE(std::regex_search(std::string("the model of stop 33"), history));
  EXPECT_TRUE(std::regex_search(std::string("(seed 002)"), history));
  EXPECT_FALSE(std::regex_search(std::string("--seed N  random seed of the day"), history));
  EXPECT_FALSE(std::regex_search(std::string("stop after 5 s"), history));
}

// docs/cli.md is generated by scripts/cli-reference.sh from the program; it must not drift.
TEST(CliHelp, CliReferenceMatchesTheProgram) {
  const std::filesystem::path src = TRUEAXIS_SOURCE_DIR;
  const std::string cmd = "bash '" + (src / "scripts/cli-reference.sh").string() + "' '" + TRUEAXIS_CLI_PATH + "'";
  const auto run = trueaxis::testing::RunShell(cmd);
  const std::string& generated = run.output;
  ASSERT_EQ(run.exit_code, 0) << generated;
  ASSERT_GT(generated.size(), 1000u);
  EXPECT_TRUE(generated == trueaxis::testing::ReadText(src / "docs/cli.md"))
      << "docs/cli.md differs from the program's --help: run `bash scripts/cli-reference.sh > docs/cli.md`";
}

}  // namespace
