// trueaxis pitch proof --machine FILE [--axis X] [--out DIR] [--markdown]
// Seed 002's before/after on the virtual machine: fine calibration, the
// once-per-lead table, re-homing the next day, verification at lead/4 with
// the table applied ahead of the motion; following error vs feed.
#include <filesystem>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "command.hpp"
#include "pitch_command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/pitch/error_file.hpp"
#include "trueaxis/pitch/proof.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::string machine, axis, out;
  std::uint64_t seed = 1;
  int day = 0;
  std::string samples_per_lead = "auto";
  std::vector<double> feeds = {1000, 5000, 10000, 20000, 40000};
  bool markdown = false;
  cli::FineCliOptions fine;
};

std::string MarkdownRow(const pitch::PitchProofResult& r) {
  auto pair = [](double b, double a) { return fmt::format("{:.1f} → {:.1f}", b, a); };
  const auto& f = r.following.empty() ? pitch::FollowingPoint{} : r.following.back();
  return fmt::format("| {} {} | {:g} / {:g} | {} | {} | {} | {} | {} | {} | {} | {:.1f} / {:.1f} / {:.1f} | {} | {:.2f} / {:.2f} @ {:g} |",
                     r.machine, r.axis, r.travel_mm, r.lead_mm, pair(r.c.before.max_error_um, r.c.after.max_error_um),
                     fmt::format("{:.2f} → {:.2f}", r.c.before.uncertainty_um, r.c.after.uncertainty_um),
                     pair(r.c.before.iso.A_um, r.c.after.iso.A_um), pair(r.c.before.iso.E_um, r.c.after.iso.E_um),
                     pair(r.c.before.iso.R_um, r.c.after.iso.R_um), pair(r.c.before.iso.B_um, r.c.after.iso.B_um),
                     pair(r.c.before_at_lead.max_error_um, r.c.after_at_lead.max_error_um), r.c.interpolation_error_um,
                     r.c.after.repeatability_3s_um, r.c.drift_um, r.c.Dominant(), f.ahead.max_abs_following_um, f.late.max_abs_following_um,
                     f.feed_mm_min);
}

void Run(const Options& o) {
  const auto machine = sim::ReadMachineFile(o.machine);
  std::vector<std::size_t> axes;
  if (o.axis.empty())
    for (std::size_t i = 0; i < machine.axes.size(); ++i) axes.push_back(i);
  else
    axes.push_back(cli::MachineAxis(machine, o.machine, o.axis));
  pitch::PitchProofOptions po;
  po.seed = o.seed;
  po.cycle = o.fine.Cycle();
  po.interpolator = o.fine.Interpolator();
  po.homing = o.fine.Homing();
  po.samples_per_lead = cli::ParseSamplesPerLead(o.samples_per_lead);
  po.verify_day = o.day;
  po.feeds_mm_min = o.feeds;
  if (!o.out.empty()) std::filesystem::create_directories(o.out);
  for (std::size_t axis : axes) {
    pitch::PitchProofResult r;
    try {
      r = pitch::RunPitchProof(machine, axis, po);
    } catch (const std::invalid_argument& e) {
      throw InputError(o.machine, e.what());
    }
    if (o.markdown) fmt::print("{}\n", MarkdownRow(r));
    else fmt::print("{}", r.Report());
    if (!o.out.empty()) {
      const std::string stem = (std::filesystem::path(o.out) / r.axis).string();
      measure::WriteMeasurementCsv(r.before_run, stem + "_fine_before.csv");
      measure::WriteMeasurementCsv(r.after_run, stem + "_fine_after.csv");
      pitch::WritePitchErrorFile(r.table, stem + ".pitch.csv");
    }
  }
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::PitchCommand(app)->add_subcommand(
      "proof", "Pitch-table before/after on the virtual machine: fine calibration, pitch table, re-homing, verification");
  cmd->add_option("--machine", o->machine, "Machine description (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--axis", o->axis, "Axis (default: every axis)");
  cmd->add_option("--seed", o->seed, "Run seed")->capture_default_str();
  cmd->add_option("--day", o->day, "0: verified right after the calibration (re-homed); N: N days later")
      ->capture_default_str()->check(CLI::Range(0, 3650));
  cmd->add_option("--samples-per-lead", o->samples_per_lead, cli::kSamplesPerLeadHelp)->capture_default_str();
  cmd->add_option("--feeds", o->feeds, "feeds of the following-error comparison, mm/min")->delimiter(',')->capture_default_str();
  cmd->add_option("--out", o->out, "write <AXIS>_fine_before.csv, <AXIS>_fine_after.csv, <AXIS>.pitch.csv here");
  cmd->add_flag("--markdown", o->markdown, "one markdown table row per axis (bench/results/pitch.md)");
  o->fine.Add(cmd);
  cmd->callback([o] { Run(*o); });
}

cli::CommandRegistrar reg("pitch_proof", Setup);

}  // namespace
