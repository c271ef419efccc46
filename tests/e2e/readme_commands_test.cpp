// Every command in the README and in the documents a new user follows (docs/getting-started.md,
// docs/tour.md) must run as written, in order, after the two quick-start commands. This test reads
// those files themselves (so every later edit of them is tested too), extracts the commands of every
// ```sh block outside a "## Quick start" section, and runs them with bash in a scratch copy of the
// repository layout (examples/, build/apps/trueaxis/trueaxis, ../shared) after
// `trueaxis demo --out out/demo` — what scripts/demo.sh leaves behind. A block that shows commands
// not to be run here is written ```text (or ```bash).
//
// `cmake --build build --target trueaxis` is left out (the scratch layout holds the built program).
// The only rewrite: the MODBUS port 1502 of the documents (and of examples/run/modbus.toml) becomes
// a free port, so parallel test runs and a server someone left running cannot collide with it.
#include <gtest/gtest.h>

#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/read_text.hpp"
#include "support/cli_runner.hpp"
#include "support/local_process.hpp"

namespace fs = std::filesystem;

namespace {

// The documents whose commands run, in this order (later ones use what earlier ones wrote).
constexpr const char* kDocuments[] = {"README.md", "docs/getting-started.md", "docs/tour.md"};

using trueaxis::testing::ReadText;

// Drops a trailing "# comment" that stands outside quotes.
std::string StripComment(const std::string& line) {
  char quote = 0;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) {
      return line.substr(0, i);
    }
  }
  return line;
}

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t");
  return s.substr(b, e - b + 1);
}

// Commands of every ```sh block except those under the heading `skipped`
// (the quick start: the two commands that run this test), backslash
// continuations joined.
std::vector<std::string> ExtractCommands(const std::string& readme, const std::string& skipped) {
  std::vector<std::string> commands;
  std::istringstream in(readme);
  std::string line;
  bool skipping = false, in_block = false, in_sh = false;
  std::string pending;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      in_sh = !in_block && line.rfind("```sh", 0) == 0;
      in_block = !in_block;
      continue;
    }
    if (!in_block && line.rfind("## ", 0) == 0) skipping = line.rfind(skipped, 0) == 0;
    if (!in_block || !in_sh || skipping) continue;
    if (!line.empty() && line.back() == '\\') {
      pending += line.substr(0, line.size() - 1) + " ";
      continue;
    }
    const std::string command = Trim(StripComment(pending + line));
    pending.clear();
    if (!command.empty()) commands.push_back(command);
  }
  return commands;
}


std::string ShellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// One bash line per README command: bounded in time, its exit code checked
// and named on failure; a background server is waited for on its port.
std::string ScriptFor(const std::vector<std::string>& commands) {
  std::string s = "set -u\ntrap 'kill $(jobs -p) 2>/dev/null' EXIT\n";
  int n = 0;
  for (const auto& c : commands) {
    ++n;
    s += "echo " + ShellQuote("### README command " + std::to_string(n) + ": " + c) + "\n";
    const bool assignment = std::regex_search(c, std::regex(R"(^[A-Za-z_][A-Za-z0-9_]*=\S+$)"));
    const bool background = c.back() == '&';
    if (assignment || c.rfind("kill ", 0) == 0) {
      s += c + "\n";
    } else if (c.rfind("until ", 0) == 0 || c.rfind("while ", 0) == 0) {
      // A wait loop a user pastes (for a server started with & to listen): bounded here.
      s += "timeout 60 bash -c " + ShellQuote(c) + " || { echo " +
           ShellQuote("README command " + std::to_string(n) + " failed: " + c) + " \"(exit $?)\"; exit 1; }\n";
    } else if (background) {
      s += c + "\n";
      std::smatch m;
      if (std::regex_search(c, m, std::regex(R"(--port\s+(\d+))"))) {
        s += "for i in $(seq 1 100); do (exec 3<>/dev/tcp/127.0.0.1/" + m[1].str() +
             ") 2>/dev/null && break; sleep 0.1; done\n";
      }
    } else {
      s += "timeout 180 " + c + " || { echo " + ShellQuote("README command " + std::to_string(n) + " failed: " + c) +
           " \"(exit $?)\"; exit 1; }\n";
    }
  }
  return s + "echo \"README commands run: " + std::to_string(n) + "\"\n";
}

TEST(ReadmeCommands, EveryCommandRunsAsWrittenInOrderAfterTheDemo) {
  const fs::path source = TRUEAXIS_SOURCE_DIR;
  const fs::path shared = fs::path(TRUEAXIS_SHARED_DATA_DIR).parent_path();
  if (!fs::exists(shared / "data")) GTEST_SKIP() << "../shared/data is absent; the README's commands read it";

  std::vector<std::string> commands;
  for (const char* document : kDocuments) {
    ASSERT_TRUE(fs::exists(source / document)) << document;
    const auto own = ExtractCommands(ReadText(source / document), "## Quick start");
    EXPECT_FALSE(own.empty()) << document << " should show the commands a user runs, in ```sh blocks";
    commands.insert(commands.end(), own.begin(), own.end());
  }
  // Fails when the sections vanish or their blocks stop being ```sh.
  ASSERT_GE(commands.size(), 60u) << "the documents should hold the commands a user runs, in ```sh blocks";

  // Commands of an optional feature this build lacks (its line in `trueaxis --help` says "not in
  // this build") are left out; scripts/test.sh builds every feature, so there every command runs.
  const std::string help = trueaxis::testing::RunCli("--help").output;
  const std::regex absent(R"((?:^|\n)\s+(\w+)\s[^\n]*\(not in this build)");
  for (auto it = std::sregex_iterator(help.begin(), help.end(), absent); it != std::sregex_iterator(); ++it) {
    const std::regex uses(R"((\$T|trueaxis) )" + (*it)[1].str() + R"(\b)");
    std::erase_if(commands, [&](const std::string& c) { return std::regex_search(c, uses); });
  }

  // Building every command (`cmake --build build --target trueaxis`, after the demo script built only
  // the demo) needs the real build tree; the scratch layout below already holds the built program.
  const auto builds = std::erase_if(
      commands, [](const std::string& c) { return c.rfind("cmake --build build --target trueaxis", 0) == 0; });
  EXPECT_GE(builds, 1u) << "the documents no longer say how to build every command after the demo";

  const std::string port = std::to_string(trueaxis::testing::FreeLoopbackPort());
  for (auto& c : commands) c = std::regex_replace(c, std::regex(R"(\b1502\b)"), port);

  const fs::path top = fs::temp_directory_path() / ("trueaxis_readme_" + std::to_string(getpid()));
  const fs::path repo = top / "repo";
  fs::remove_all(top);
  fs::create_directories(repo / "build/apps/trueaxis");
  fs::copy(source / "examples", repo / "examples", fs::copy_options::recursive);
  fs::create_symlink(TRUEAXIS_CLI_PATH, repo / "build/apps/trueaxis/trueaxis");
  fs::create_directory_symlink(shared, top / "shared");
  {
    const fs::path modbus = repo / "examples/run/modbus.toml";
    const std::string text = std::regex_replace(ReadText(modbus), std::regex(R"(\b1502\b)"), port);
    std::ofstream(modbus) << text;
  }
  // First what scripts/demo.sh runs, from the repository root: out/demo (campaign, model, day, history).
  commands.insert(commands.begin(), "./build/apps/trueaxis/trueaxis demo --out out/demo --quiet");

  std::ofstream(top / "readme.sh") << ScriptFor(commands);
  const std::string cmd = "cd " + ShellQuote(repo.string()) + " && bash ../readme.sh 2>&1";
  const auto run = trueaxis::testing::RunShell(cmd);
  const std::string& output = run.output;
  const int code = run.exit_code;
  // The tail is what matters on failure: the failing command and its message.
  EXPECT_EQ(code, 0) << output.substr(output.size() > 6000 ? output.size() - 6000 : 0);
  EXPECT_NE(output.find("README commands run: " + std::to_string(commands.size())), std::string::npos);
  if (code == 0) fs::remove_all(top);
}

TEST(ReadmeCommands, ExtractionJoinsContinuationsAndDropsComments) {
  const std::string readme =
      "## Quick start\n```sh\nscripts/demo.sh\n```\n## Using it\ntext\n```sh\nT=./t\n"
      "$T a --x \"a # b\"   # comment\n$T b \\\n    --c 1\n```\n```json\n{}\n```\n## Other\n```sh\nnot me\n```\n";
  const auto c = ExtractCommands(readme, "## Quick start");
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], "T=./t");
  EXPECT_EQ(c[1], "$T a --x \"a # b\"");
  EXPECT_EQ(c[2], "$T b      --c 1");
  EXPECT_EQ(c[3], "not me");
}

}  // namespace
