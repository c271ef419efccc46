#pragma once
// Which heading of `trueaxis --help` each top-level command stands under: one table, here.
// A command missing from the table is shown under Tools (tests/e2e/cli_help_test.cpp lists
// every command that is missing, so a new command gets its place on purpose).
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace trueaxis::cli {

// The headings, in the order `--help` shows them.
inline constexpr std::array<std::string_view, 5> kCommandGroups = {
    "Measure (laser runs, temperatures, calibration campaigns)",
    "Model (fit, predict, data-driven thermal models)",
    "Compensate (live correction, controller tables)",
    "Shop (many machines, remote monitoring)",
    "Tools (the demo, the virtual machine, MODBUS)",
};
inline constexpr std::size_t kToolsGroup = 4;

// Top-level command → index into kCommandGroups.
inline constexpr std::pair<std::string_view, std::size_t> kCommandGroupOf[] = {
    {"analyze", 0},     {"calibrate", 0}, {"campaign", 0}, {"history", 0},   {"measurement", 0}, {"signal", 0},
    {"fit", 1},         {"predict", 1},   {"thermal", 1},  {"tool", 1},      {"vision", 1},      {"fiveaxis", 1},
    {"export", 2},      {"pitch", 2},     {"run", 2},      {"terminal", 2},  {"server", 3},      {"web", 3},
    {"user", 3},        {"demo", 4},      {"sim", 4},      {"modbus", 4},
};

// The group index of a top-level command, or nothing when the table does not name it.
inline std::optional<std::size_t> GroupOf(std::string_view command) {
  for (const auto& [name, group] : kCommandGroupOf)
    if (name == command) return group;
  return std::nullopt;
}

}  // namespace trueaxis::cli
