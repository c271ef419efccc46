#include "pitch_command.hpp"

#include "command.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {

CLI::App* PitchCommand(CLI::App& app) {
  return CommandGroup(app, "pitch", "Lead-screw pitch error: once-per-lead error files, feed-forward, proof");
}

std::size_t MachineAxis(const sim::MachineDescription& machine, const std::string& machine_path, const std::string& axis) {
  if (axis.empty()) return 0;
  const int i = machine.AxisIndex(axis);
  if (i < 0) {
    std::string known;
    for (const auto& a : machine.axes) known += (known.empty() ? "" : ", ") + a.name;
    throw InputError(machine_path, 0, "--axis", fmt::format("the machine has no axis '{}' (it has: {})", axis, known));
  }
  return static_cast<std::size_t>(i);
}

int ParseSamplesPerLead(const std::string& text) {
  if (text == "auto") return 0;
  std::size_t used = 0;
  int n = 0;
  try {
    n = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || used == 0 || n < 1 || n > 64)
    throw InputError("command line", 0, "--samples-per-lead", fmt::format("'{}' is neither auto nor a whole number 1…64", text));
  return n;
}

void FineCliOptions::Add(CLI::App* cmd) {
  cmd->add_option("--per-lead", per_lead, "targets every lead/N (4 resolves the lead's first harmonic)")
      ->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--runs", runs, "bidirectional runs")->capture_default_str()->check(CLI::Range(2, 20));
  cmd->add_option("--feed", feed_mm_min, "feed between targets, mm/min")->capture_default_str()->check(CLI::PositiveNumber);
  cmd->add_option("--dwell-s", dwell_s, "stop at each target, s")->capture_default_str()->check(CLI::NonNegativeNumber);
  cmd->add_option("--cycle-ms", cycle_ms, "interpolation cycle of the virtual CNC, ms (CNCs: 1-4)")
      ->capture_default_str()->check(CLI::Range(0.1, 100.0));
  cmd->add_option("--homing", homing, "switch+index (switch, then the encoder index) | switch (switch only)")->capture_default_str();
  cmd->add_option("--feed-forward", feed_forward, "how the interpolator applies a table: ahead (feed-forward) | late | off")
      ->capture_default_str();
}

pitch::FineCycleOptions FineCliOptions::Cycle() const {
  pitch::FineCycleOptions c;
  c.per_lead = per_lead;
  c.runs = runs;
  c.feed_mm_min = feed_mm_min;
  c.dwell_s = dwell_s;
  return c;
}

sim::InterpolatorOptions FineCliOptions::Interpolator() const {
  sim::InterpolatorOptions io;
  io.cycle_s = cycle_ms / 1000.0;
  auto f = sim::ParseFeedForward(feed_forward);
  if (!f) throw InputError("command line", 0, "--feed-forward", fmt::format("'{}' is not ahead, late or off", feed_forward));
  io.mode = *f;
  return io;
}

sim::HomingMethod FineCliOptions::Homing() const {
  auto h = sim::ParseHomingMethod(homing);
  if (!h) throw InputError("command line", 0, "--homing", fmt::format("'{}' is not switch+index or switch", homing));
  return *h;
}

}  // namespace trueaxis::cli
