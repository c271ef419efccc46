// trueaxis pitch table --measurement FILE | --model FILE --axis X  --out FILE.pitch.csv
// Writes the once-per-lead pitch error file (docs/pitch-error-file.md) and
// prints the seed-002 decomposition of the run it came from.
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "pitch_command.hpp"
#include "trueaxis/analysis/decomposition.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/measure/measurement_file.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/pitch/error_file.hpp"

namespace {

using namespace trueaxis;

struct Options {
  std::string measurement, model, axis, out;
  double lead_mm = 0;
  double reference_mm = std::nan("");
  double travel_mm = std::nan("");
  std::string samples_per_lead = "auto";
  int harmonics = 2;
  cli::MeasurementInputOptions input;
};

void Run(const Options& o) {
  if (o.measurement.empty() == o.model.empty())
    throw InputError("command line", 0, "--measurement", "give exactly one of --measurement or --model (with --axis)");
  RefuseOutputOverInput(o.out, {o.measurement, o.model, o.input.column_map}, "--out");
  int samples_per_lead = cli::ParseSamplesPerLead(o.samples_per_lead);
  pitch::PitchErrorTable table;
  if (!o.measurement.empty()) {
    const auto m = o.input.Read(o.measurement);
    pitch::TableFromMeasurementOptions to;
    to.lead_mm = o.lead_mm;
    to.samples_per_lead = samples_per_lead;
    to.reference_mm = o.reference_mm;
    if (samples_per_lead == 0) {
      const pitch::SamplesPerLeadChoice choice = pitch::ChooseSamplesPerLead(m, to);
      to.samples_per_lead = choice.samples_per_lead;
      fmt::print("table: {}\n", choice.Describe());
      if (!choice.within_tolerance) fmt::print(stderr, "warning: {}: {}\n", o.measurement, choice.Describe());
    }
    table = pitch::TableFromMeasurement(m, to);
    if (!o.axis.empty()) table.axis = o.axis;
    // The travel the axis moves in: --travel-mm, else the run's travel_mm metadata.
    double travel_mm = o.travel_mm;
    if (std::isnan(travel_mm))
      if (auto meta = m.Meta("travel_mm"))
        if (auto v = ParseDouble(Trim(*meta)); v && std::isfinite(*v) && *v > 0) travel_mm = *v;
    if (auto w = pitch::UncoveredTravelWarning(table.measured_from_mm, table.measured_to_mm, travel_mm, o.measurement)) {
      fmt::print(stderr, "warning: {}\n", *w);
      table.provenance.push_back(fmt::format("measured {}…{} mm of the travel 0…{} mm", table.measured_from_mm,
                                             table.measured_to_mm, travel_mm));
    }
    analysis::DecompositionOptions d;
    d.lead_mm = table.lead_mm;
    d.harmonics = o.harmonics;
    const auto dec = analysis::Decompose(analysis::Evaluate(m), d);
    fmt::print("{}", dec.BriefReport());
    for (const auto& h : dec.harmonics)
      if (!h.resolved) fmt::print("  harmonic {} ({:.4g} mm): {}\n", h.order, h.period_mm, h.note);
    for (const auto& n : dec.notes) fmt::print("  note: {}\n", n);
    fmt::print("table interpolation error against this run's targets: max {:.3f} um\n",
               pitch::MaxInterpolationErrorUm(table, m));
  } else {
    if (o.axis.empty()) throw InputError("command line", 0, "--axis", "required with --model");
    if (!(o.lead_mm > 0)) throw InputError("command line", 0, "--lead-mm", "required with --model (the model has no lead)");
    const auto cm = model::ReadModelFile(o.model);
    const auto* axis = cm.FindAxis(o.axis);
    if (!axis) throw InputError(o.model, 0, "--axis", fmt::format("the model has no axis '{}'", o.axis));
    if (samples_per_lead == 0) {
      // A model holds no laser run to choose from: once per lead, unless told.
      samples_per_lead = 1;
      fmt::print("table: once per lead (from a model; --samples-per-lead N for a finer table)\n");
    }
    table = pitch::TableFromModel(*axis, o.lead_mm, samples_per_lead, {}, o.model);
  }
  pitch::WritePitchErrorFile(table, o.out);
  fmt::print("axis {}: {} samples every {:.4g} mm ({} per lead of {} mm), {}…{} mm, vouched for {}…{} mm -> {}\n",
             table.axis, table.size(), table.SpacingMm(), table.samples_per_lead, table.lead_mm, table.position_mm.front(),
             table.position_mm.back(), table.VouchedFromMm(), table.VouchedToMm(), o.out);
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = cli::PitchCommand(app)->add_subcommand("table", "Write a pitch error file (samples per lead fitted to the screw) from a fine laser run or a fitted model");
  cmd->add_option("--measurement", o->measurement, "laser run (canonical CSV, ecmc .dat or a mapped laser export) with targets at lead spacing or finer")
      ->check(CLI::ExistingFile);
  cli::AddMeasurementInputOptions(cmd, o->input);
  cmd->add_option("--model", o->model, "fitted model JSON (cold state)")->check(CLI::ExistingFile);
  cmd->add_option("--axis", o->axis, "axis name (required with --model; overrides the run's)");
  cmd->add_option("--lead-mm", o->lead_mm, "screw lead (default: the run's lead_mm metadata)")->check(CLI::PositiveNumber);
  cmd->add_option("--reference-mm", o->reference_mm, "grid origin (default: the run's reference_mm, else its first target)");
  cmd->add_option("--travel-mm", o->travel_mm,
                  "the axis's travel 0…T, to warn when the run leaves part of it unmeasured (default: the run's travel_mm)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--samples-per-lead", o->samples_per_lead, cli::kSamplesPerLeadHelp)->capture_default_str();
  cmd->add_option("--harmonics", o->harmonics, "lead harmonics tried by the decomposition")->capture_default_str()->check(CLI::Range(0, 8));
  cmd->add_option("--out", o->out, "pitch error file to write")->required();
  cmd->callback([o, cmd] {
    // Not given is NaN (the run's reference): a given `--reference-mm nan` must not read as that.
    if (cmd->count("--reference-mm") > 0)
      if (auto why = ImplausiblePositionMm(o->reference_mm)) throw InputError("command line", 0, "--reference-mm", *why);
    Run(*o);
  });
}

cli::CommandRegistrar reg("pitch_table", Setup);

}  // namespace
