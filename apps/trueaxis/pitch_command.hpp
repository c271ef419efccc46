#pragma once
// The `trueaxis pitch` parent subcommand (lead-screw pitch error tables,
// docs/pitch-error-file.md); its children attach to it from their own files.
#include <CLI/CLI.hpp>

namespace trueaxis::cli {

CLI::App* PitchCommand(CLI::App& app);

}  // namespace trueaxis::cli

#include <cstddef>
#include <string>

#include "trueaxis/pitch/fine_cycle.hpp"
#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::cli {

// Index of the named axis of the machine (empty: the first axis); InputError otherwise.
std::size_t MachineAxis(const sim::MachineDescription& machine, const std::string& machine_path, const std::string& axis);

// `--samples-per-lead auto|N` of `pitch table` and `pitch proof`: 0 for auto (chosen from the
// laser run, pitch::ChooseSamplesPerLead), else N in 1…64; InputError naming the option otherwise.
int ParseSamplesPerLead(const std::string& text);
inline constexpr const char* kSamplesPerLeadHelp =
    "table samples per lead: auto (the fewest that fit the run's mean deviations within its scatter, 1 sigma, at "
    "least 0.5 um) or 1..64 (1: once per lead)";

// Options shared by `sim fine` and `pitch proof` (fine cycle, interpolator, homing).
struct FineCliOptions {
  int per_lead = 4;
  int runs = 3;
  double feed_mm_min = 2000;
  double dwell_s = 1;
  double cycle_ms = 2;
  std::string homing = "switch+index";
  std::string feed_forward = "ahead";
  void Add(CLI::App* cmd);
  pitch::FineCycleOptions Cycle() const;
  sim::InterpolatorOptions Interpolator() const;
  sim::HomingMethod Homing() const;
};

}  // namespace trueaxis::cli
