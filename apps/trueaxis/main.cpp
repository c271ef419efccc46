// trueaxis: measure, model and compensate machine-tool axis errors.
// Subcommands live one per file (cmd_*.cpp) and register themselves; their --help heading comes
// from command_groups.hpp.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "command.hpp"
#include "command_groups.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {
std::vector<CommandEntry>& Registry() {
  static std::vector<CommandEntry> registry;
  return registry;
}
}  // namespace trueaxis::cli

namespace {

using namespace trueaxis::cli;

// The top-level command a registry entry belongs to: "sim_shop" → "sim".
std::string_view TopLevelName(std::string_view entry) { return entry.substr(0, entry.find('_')); }

std::size_t GroupRank(std::string_view entry) { return GroupOf(TopLevelName(entry)).value_or(kToolsGroup); }

std::size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// The candidate nearest to `word`, when it is near enough to be a typing slip.
std::optional<std::string> Nearest(std::string_view word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const std::size_t d = EditDistance(word, c);
    if (d < best_distance) best_distance = d, best = c;
  }
  return best;
}

const CLI::Option* FindOption(const CLI::App* app, std::string_view token) {
  for (; app != nullptr; app = app->get_parent())
    for (const CLI::Option* opt : app->get_options()) {
      if (token.rfind("--", 0) == 0) {
        for (const auto& l : opt->get_lnames())
          if (token.substr(2) == l) return opt;
      } else {
        for (const auto& s : opt->get_snames())
          if (token.substr(1) == s) return opt;
      }
    }
  return nullptr;
}

std::string DidYouMean(const std::optional<std::string>& nearest) {
  return nearest ? fmt::format("; did you mean '{}'?", *nearest) : std::string();
}

// After a usage error: the command or option the user mistyped, said with the nearest
// spelling that exists ("unknown command 'analize'; did you mean 'analyze'?"), or nothing
// when the error is of another kind (CLI11's own message is then printed).
std::optional<std::string> UnknownWord(const CLI::App& app, int argc, char** argv) {
  const CLI::App* current = &app;
  std::string path = "trueaxis";
  int values_to_skip = 0;  // words that are the values of the option before them
  for (int i = 1; i < argc; ++i) {
    const std::string_view token = argv[i];
    if (token == "--") return std::nullopt;
    const bool number = token.size() > 1 && (std::isdigit(static_cast<unsigned char>(token[1])) || token[1] == '.');
    if (token.size() > 1 && token[0] == '-' && !number) {
      const std::string_view name = token.substr(0, token.find('='));
      const CLI::Option* opt = FindOption(current, name);
      if (opt == nullptr) {
        std::vector<std::string> names;
        for (const CLI::Option* o : current->get_options())
          if (!o->get_group().empty())
            for (const auto& l : o->get_lnames()) names.push_back("--" + l);
        return fmt::format("unknown option '{}' for '{}'{}\nrun '{} --help' for its options", name, path,
                           DidYouMean(Nearest(name, names)), path);
      }
      values_to_skip = token.find('=') != std::string_view::npos ? 0 : opt->get_items_expected_max();
      continue;
    }
    if (values_to_skip > 0) {
      --values_to_skip;
      continue;
    }
    const auto children = current->get_subcommands({});
    if (children.empty()) continue;  // a positional value of a command without subcommands
    const auto child = std::find_if(children.begin(), children.end(),
                                    [&](const CLI::App* c) { return c->get_name() == token; });
    if (child == children.end()) {
      std::vector<std::string> names;
      for (const CLI::App* c : children) names.push_back(c->get_name());
      return fmt::format("unknown command '{}'{}{}\nrun '{} --help' for the commands", token,
                         current == &app ? std::string() : fmt::format(" of '{}'", path),
                         DidYouMean(Nearest(token, names)), path);
    }
    current = *child;
    path += " " + std::string(token);
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  // Named, so that help and messages say `trueaxis` however the program was started.
  CLI::App app{"trueaxis — measure, model and compensate the geometric and thermal errors of machine-tool axes", "trueaxis"};
  app.set_version_flag("--version", "trueaxis " TRUEAXIS_VERSION);  // the project's version (CMakeLists.txt)
  app.require_subcommand(1);
  app.footer("Start with `trueaxis demo`; every command has --help; docs/cli.md lists them all.");
  auto& registry = Registry();
  std::sort(registry.begin(), registry.end(), [](const auto& a, const auto& b) {
    return std::pair(GroupRank(a.name), a.name) < std::pair(GroupRank(b.name), b.name);
  });
  for (const auto& entry : registry) entry.setup(app);
  for (CLI::App* sub : app.get_subcommands({}))
    sub->group(std::string(kCommandGroups[GroupOf(sub->get_name()).value_or(kToolsGroup)]));
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    // A command that failed after printing why (not a usage error): its own exit code.
    return e.get_exit_code();
  } catch (const CLI::ParseError& e) {
    // CLI11 prints the message (or the help) itself; its own exit codes
    // (104–109 …) are folded into ours: help/version is success, any usage
    // error is bad input like a bad file (README: exit code 2).
    if (e.get_exit_code() != 0) {
      if (const auto unknown = UnknownWord(app, argc, argv)) {
        fmt::print(stderr, "error: {}\n", *unknown);
        return kExitBadInput;
      }
    }
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
