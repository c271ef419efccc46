// trueaxis fit --out model.json INPUTS… [--manifest DIR/manifest.json]
//              [--geometric auto|poly|table] [--max-degree N] [--report fit.html]
//              [--previous old.json [--add-to-previous]] [--keys nut,bearing] [--reference-mm P]
//              [--rho R] [--ambient-sensor NAME] [--axis X] [--state S] [--columns …|--column-map F] [--full]
// Fits the composite geometric + thermal model (seed 000) per axis and per
// direction from measurement files of several thermal states and writes the
// model file (docs/model-file.md). With --previous the new model is the next
// revision of that one: revision + 1, parent_sha256 and the lineage recorded.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "utc_now.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/progress.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/modelfit/fit_report.hpp"
#include "trueaxis/modelfit/model_fit.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"

namespace trueaxis::cli {
namespace {

struct FitCliOptions {
  std::string out;
  std::vector<std::string> inputs;
  std::string manifest;
  std::string geometric = "auto";
  int max_degree = 8;
  std::string report;
  std::string previous;
  std::vector<std::string> keys;
  double reference_mm = std::numeric_limits<double>::quiet_NaN();
  double rho = std::numeric_limits<double>::quiet_NaN();
  double cte = std::numeric_limits<double>::quiet_NaN();
  bool rho_fit = false;
  std::string ambient_sensor;
  std::string axis;
  std::string state;  // for an input file that names none (an ecmc .dat, a laser export)
  MeasurementInputOptions input;
  int max_keys = 3;
  double max_key_correlation = 0.98;
  double secondary_key_ridge = model::FitOptions{}.secondary_key_ridge;
  std::string key_offsets = "auto";
  std::string motion_heat = "auto";
  std::vector<double> motion_lag_grid_s = model::FitOptions{}.motion_lag_grid_s;
  bool reuse_sources = false;
  bool full = false;
  std::vector<double> lag_grid_s = model::FitOptions{}.key_lag_grid_s;
  std::vector<double> lag_fall_grid = model::FitOptions{}.key_lag_fall_grid;
  std::vector<double> coolant_loss_grid_s = model::FitOptions{}.coolant_loss_grid_s;
  bool no_fallback_models = false;
  bool coolant_soak = false;
  std::vector<std::string> redundant;  // "y_nut,y_nut_b" per group
  double envelope_margin = model::FitOptions{}.tan_beta_margin;
};

// How much the geometric part moved against the previous revision, per axis and direction.
std::string CompareWithPrevious(const model::CompositeModel& prev, const model::CompositeModel& next) {
  std::string out;
  for (const auto& a : next.axes) {
    const auto* p = prev.FindAxis(a.axis);
    if (!p) {
      out += fmt::format("  axis {}: new (not in the previous revision)\n", a.axis);
      continue;
    }
    for (Direction d : {Direction::kForward, Direction::kReverse}) {
      const auto& g = a.For(d).geometric;
      const double lo = g.kind == model::GeometricError::Kind::kTable ? g.table_position_mm.front() : g.center_mm - g.half_span_mm;
      const double hi = g.kind == model::GeometricError::Kind::kTable ? g.table_position_mm.back() : g.center_mm + g.half_span_mm;
      double max_diff = 0;
      for (int i = 0; i <= 200; ++i) {
        const double x = lo + (hi - lo) * i / 200.0;
        max_diff = std::max(max_diff, std::abs(g.Evaluate(x) - p->For(d).geometric.Evaluate(x)));
      }
      out += fmt::format("  axis {} {}: Er(x) changed by up to {:.3f} µm over {:.1f} … {:.1f} mm\n", a.axis,
                         DirectionSymbol(d), max_diff, lo, hi);
    }
    if (a.key_sensors != p->key_sensors)
      out += fmt::format("  axis {}: key sensors changed ({} → {})\n", a.axis, fmt::join(p->key_sensors, ","),
                         fmt::join(a.key_sensors, ","));
    std::vector<double> old_lag, new_lag;
    for (std::size_t i = 0; i < p->key_sensors.size(); ++i) old_lag.push_back(p->KeyLagS(i));
    for (std::size_t i = 0; i < a.key_sensors.size(); ++i) new_lag.push_back(a.KeyLagS(i));
    if (old_lag != new_lag)
      out += fmt::format("  axis {}: key-sensor lag τ changed ({} s → {} s)\n", a.axis, fmt::join(old_lag, "/"),
                         fmt::join(new_lag, "/"));
  }
  return out;
}

// --state: the thermal state of the one input file that names none (`# state:` line, manifest):
// an ecmc .dat or a laser software's export carries no state. Given to several such files it would
// make them one state twice, so it is refused then; a file that names its own state keeps it.
void ApplyStateOption(const std::string& label, std::vector<model::FitState>& states) {
  std::vector<model::FitState*> unnamed;
  for (auto& s : states)
    if (s.label.empty()) unnamed.push_back(&s);
  if (unnamed.empty())
    throw InputError("command line", 0, "--state",
                     "every input file names its own state ('# state:' line or manifest); --state would change none");
  if (unnamed.size() > 1)
    throw InputError("command line", 0, "--state",
                     fmt::format("{} input files name no state ({}, …): --state names the state of one file; give the "
                                 "others theirs in a manifest or with `trueaxis measurement convert --state`",
                                 unnamed.size(), unnamed[0]->path));
  auto& s = *unnamed[0];
  const model::FitState labelled = model::MakeFitState(s.measurement, label, "", s.sha256);
  s.label = labelled.label;
  s.kind = labelled.kind;
  s.coolant = labelled.coolant;
}

void RunFit(const FitCliOptions& o) {
  if (o.inputs.empty() && o.manifest.empty() && !o.reuse_sources)
    throw InputError("command line", 0, "INPUTS", "give measurement files and/or --manifest");
  if (o.reuse_sources && o.previous.empty())
    throw InputError("command line", 0, "--add-to-previous", "needs --previous MODEL");
  model::FitOptions fo;
  if (o.geometric == "poly" || o.geometric == "polynomial") fo.geometric = model::FitOptions::Geometric::kPolynomial;
  else if (o.geometric == "table") fo.geometric = model::FitOptions::Geometric::kTable;
  else if (o.geometric == "auto") fo.geometric = model::FitOptions::Geometric::kAuto;
  else throw InputError("command line", 0, "--geometric", fmt::format("'{}' is not 'poly', 'table' or 'auto'", o.geometric));
  fo.max_degree = o.max_degree;
  fo.key_sensors = o.keys;
  fo.max_key_sensors = o.max_keys;
  fo.max_key_correlation = o.max_key_correlation;
  fo.secondary_key_ridge = o.secondary_key_ridge;
  if (o.key_offsets == "auto") fo.key_offsets = model::FitOptions::KeyOffsets::kAuto;
  else if (o.key_offsets == "on") fo.key_offsets = model::FitOptions::KeyOffsets::kOn;
  else if (o.key_offsets == "off") fo.key_offsets = model::FitOptions::KeyOffsets::kOff;
  else throw InputError("command line", 0, "--key-offsets", fmt::format("'{}' is not 'auto', 'on' or 'off'", o.key_offsets));
  if (o.motion_heat == "auto") fo.motion_heat = model::FitOptions::MotionHeat::kAuto;
  else if (o.motion_heat == "on") fo.motion_heat = model::FitOptions::MotionHeat::kOn;
  else if (o.motion_heat == "off") fo.motion_heat = model::FitOptions::MotionHeat::kOff;
  else throw InputError("command line", 0, "--motion-heat", fmt::format("'{}' is not 'auto', 'on' or 'off'", o.motion_heat));
  fo.motion_lag_grid_s = o.motion_lag_grid_s;
  fo.reference_position_mm = o.reference_mm;
  fo.rho_um_per_mm_per_c = o.rho;
  fo.cte_um_per_m_c = o.cte;
  fo.fit_rho_with_cte = o.rho_fit;
  fo.ambient_sensor = o.ambient_sensor;
  fo.default_axis = o.axis;
  fo.key_lag_grid_s = o.lag_grid_s;
  fo.key_lag_fall_grid = o.lag_fall_grid;
  fo.coolant_loss_grid_s = o.coolant_loss_grid_s;
  if (o.coolant_loss_grid_s.size() == 1 && o.coolant_loss_grid_s[0] < 0) fo.coolant_loss_grid_s.clear();
  fo.tan_beta_margin = o.envelope_margin;
  fo.fallback_models = !o.no_fallback_models;
  fo.coolant_soak_constraint = o.coolant_soak;
  for (const auto& group : o.redundant) {
    std::vector<std::string> names;
    std::string name;
    for (std::istringstream in(group); std::getline(in, name, ',');)
      if (!name.empty()) names.push_back(name);
    if (names.size() < 2)
      throw InputError("command line", 0, "--redundant", fmt::format("'{}': give two or more sensor names, comma separated", group));
    fo.redundant_groups.push_back(std::move(names));
  }
  std::string why;
  if (!fo.IsValid(&why)) throw InputError("command line", 0, "options", why);

  // Read the previous model first: a bad --previous must fail before any work.
  std::unique_ptr<model::CompositeModel> prev;
  std::string prev_sha;
  if (!o.previous.empty()) {
    prev = std::make_unique<model::CompositeModel>(model::ReadModelFile(o.previous));
    prev_sha = model::Sha256OfFile(o.previous);
  }

  const auto read = o.input.Resolve();
  std::vector<model::FitState> states;
  if (o.reuse_sources) {
    states = model::LoadPreviousSources(*prev, o.previous, read);
    // A file given again on the command line is not counted twice.
    for (auto& s : model::LoadFitStates(o.inputs, o.manifest, read)) {
      bool dup = false;
      for (const auto& old : states) dup = dup || old.sha256 == s.sha256;
      if (!dup) states.push_back(std::move(s));
    }
  } else {
    states = model::LoadFitStates(o.inputs, o.manifest, read);
  }
  if (!o.state.empty()) ApplyStateOption(o.state, states);
  // A redundant probe the files do not have would silently change nothing: refused.
  for (const auto& group : fo.redundant_groups)
    for (const auto& name : group) {
      bool known = false;
      for (const auto& st : states) {
        const auto& names = st.measurement.sensor_names;
        known = known || std::find(names.begin(), names.end(), name) != names.end();
      }
      if (!known)
        throw InputError("command line", 0, "--redundant",
                         fmt::format("'{}' is not a sensor of the measurement files (no t_{}_c column)", name, name));
    }
  // Neither output may be written over a file this fit reads (a measurement, the manifest, its
  // temperature log), nor over the other output. --previous may be --out: it is read in full above
  // and the new revision records its sha256 as parent (docs/model-file.md).
  std::vector<std::string> read_paths = o.inputs;
  read_paths.push_back(o.manifest);
  for (const auto& st : states) {
    read_paths.push_back(st.path);
    read_paths.push_back(st.temperature_log);
  }
  RefuseOutputOverInput(o.out, read_paths, "--out");
  read_paths.push_back(o.previous);
  read_paths.push_back(o.out);
  RefuseOutputOverInput(o.report, read_paths, "--report");
  fo.created_utc = UtcNow();  // the clock is read here, at the edge, not by the fit
  auto progress = ProgressLine::OnStderr("fit");
  fo.progress = [&](std::size_t done, std::size_t total, const std::string& what) { progress.Step(done, total, what); };
  auto result = model::FitCompositeModel(states, fo);
  progress.Finish();
  auto& m = result.model;
  if (prev) {
    m.revision = prev->revision + 1;
    m.parent_sha256 = prev_sha;
    m.lineage = prev->lineage;
    m.lineage.push_back({prev->revision, prev_sha, prev->created_utc});
    if (m.machine.empty()) m.machine = prev->machine;
  }
  model::WriteModelFile(m, o.out);
  if (!o.report.empty()) model::WriteFitReportHtml(result, states, o.report);

  std::cout << (o.full ? result.summary.FullReport() : result.summary.BriefReport());
  if (prev) std::cout << fmt::format("changes against revision {} ({}):\n{}", prev->revision, o.previous,
                                     CompareWithPrevious(*prev, m));
  std::cout << fmt::format("wrote {} (revision {}, {} axis/axes, {} source file(s), sha256 {})\n", o.out, m.revision,
                           m.axes.size(), m.sources.size(), model::Sha256OfFile(o.out));
  if (!o.report.empty()) std::cout << fmt::format("wrote {}\n", o.report);
}

void Setup(CLI::App& app) {
  auto opts = std::make_shared<FitCliOptions>();
  auto* cmd = app.add_subcommand("fit", "Fit the composite error model (geometric + fan-shaped thermal) per axis and direction");
  cmd->add_option("--out", opts->out, "Model file to write (JSON, docs/model-file.md)")->required();
  cmd->add_option("inputs", opts->inputs, "Measurement files (canonical CSV, ecmc .dat or a mapped laser export), one thermal state each ('# state:' metadata)");
  cmd->add_option("--manifest", opts->manifest, "Campaign manifest.json listing files and their states");
  cmd->add_option("--geometric", opts->geometric, "Geometric part: poly (degree chosen by CV), table (one value per sample), or auto (table when the polynomial leaves a systematic pattern)")
      ->capture_default_str();
  cmd->add_option("--max-degree", opts->max_degree, "Highest polynomial degree tried")->capture_default_str();
  cmd->add_option("--report", opts->report, "Write an HTML fit report (measured vs model per state)");
  cmd->add_option("--previous", opts->previous, "Model this fit replaces: revision+1, lineage recorded");
  cmd->add_option("--keys", opts->keys, "Key sensors to use instead of selecting them (comma separated)")
      ->delimiter(',')
      ->allow_extra_args(false);  // --keys a,b file.csv: the file stays an input
  cmd->add_option("--coolant-loss-grid-s", opts->coolant_loss_grid_s,
                  "Coolant memory: loss time constants (s) tried with one set of gains for every state (comma "
                  "separated, e.g. 0,600,1200,2400,4800,9600; default none, -1 also: gains per coolant state)")
      ->delimiter(',')
      ->allow_extra_args(false)
      ->capture_default_str();
  cmd->add_flag("--coolant-soak", opts->coolant_soak,
                "A coolant's own gains keep the off-coolant response to a soak: with two key sensors or more, the sum "
                "of their gains (and of the keys' and the room's shifts) held at the off gains' (opt-in; "
                "bench/results/zoo.md)");
  cmd->add_flag("--no-fallback-models", opts->no_fallback_models,
               "Fit no fallback models (by default an axis with key sensors is also fitted without each of "
               "them, twice — its keys re-chosen from the other sensors, and the model's other keys — and without its "
               "room sensor, for the compensator to average when that sensor is lost; docs/model-file.md)");
  cmd->add_option("--redundant", opts->redundant,
                  "Redundant probes at one place, comma separated (e.g. y_nut,y_nut_b; repeat for more groups): the "
                  "temperature pipeline loses them together when they disagree, so a fallback fitted without one "
                  "does without the others too")
      ->allow_extra_args(false);
  cmd->add_option("--envelope-margin", opts->envelope_margin,
                  "Fitted envelope of key rises and tanβ, widened by this fraction of its width (negative: none)")
      ->capture_default_str();
  cmd->add_option("--lag-grid-s", opts->lag_grid_s,
                  "Key-sensor lag time constants τ (s) tried by cross-validation (comma separated); 0 alone: no lag")
      ->delimiter(',')
      ->allow_extra_args(false)  // one token: the measurement files after it stay positional
      ->capture_default_str();
  cmd->add_option("--lag-fall-grid", opts->lag_fall_grid,
                  "Factors tried for a cooling key's longer lag τ, jointly with --lag-grid-s (1: one τ both ways; "
                  "docs/model-file.md step 7)")
      ->delimiter(',')
      ->allow_extra_args(false)  // one token: the measurement files after it stay positional
      ->capture_default_str();
  cmd->add_option("--max-keys", opts->max_keys, "Most key sensors the selection may choose")->capture_default_str();
  cmd->add_option("--max-key-correlation", opts->max_key_correlation,
                  "Candidates whose rises correlate more than this with a chosen key are skipped")
      ->capture_default_str();
  cmd->add_option("--secondary-key-ridge", opts->secondary_key_ridge,
                  "Ridge λ on the gains of every key after the first (unit-norm columns; 0: plain least squares)")
      ->capture_default_str();
  cmd->add_option("--key-offsets", opts->key_offsets,
                  "Each key's own pivot (its rise also shifts the error over the travel): auto (by cross-validation), "
                  "on, off (one pivot Px, the fan-shaped model's form)")
      ->capture_default_str();
  cmd->add_option("--motion-heat", opts->motion_heat,
                  "The axis's feed, lagged, as one more key of the thermal slope (needs the manifest's temperature "
                  "log with <axis>_travel_mm): auto (kept by cross-validation; without travel columns not tried), on, off (the temperature keys only)")
      ->capture_default_str();
  cmd->add_option("--motion-lag-grid-s", opts->motion_lag_grid_s,
                  "Lag τ values (s) tried for the motion-heat input, by the same cross-validation")
      ->delimiter(',')
      ->capture_default_str();
  cmd->add_option("--reference-mm", opts->reference_mm, "Reference point Px in mm (default: metadata or fitted)");
  cmd->add_option("--rho", opts->rho,
                  "ρ in µm/mm/°C (default: −cte/1000 when the CTE is known, else fitted from the room's changes)");
  cmd->add_option("--cte", opts->cte,
                  "CTE of the axis's position feedback in µm/m/°C: the ball screw's with a rotary encoder (steel about "
                  "11.5), the scale's with a linear scale; gives ρ = −cte/1000, the soak that holds in every season "
                  "(default: the cold file's '# cte_um_per_m_c:')");
  cmd->add_flag("--rho-fit", opts->rho_fit,
                "Fit ρ from the room's changes over the states even when the CTE is known (it then extrapolates to "
                "rooms outside them, as in another season)");
  cmd->add_option("--ambient-sensor", opts->ambient_sensor, "Ambient sensor name ('none' for no ambient term)");
  cmd->add_option("--axis", opts->axis, "Axis for files without '# axis:' metadata");
  cmd->add_option("--state", opts->state,
                  "Thermal state (cold, heated-1, ambient-24, …) of the one input file that names none, e.g. an ecmc "
                  ".dat or a laser software's export");
  AddMeasurementInputOptions(cmd, opts->input);
  cmd->add_flag("--add-to-previous", opts->reuse_sources,
                "Re-fit on the previous model's source files (hash-checked) plus the new INPUTS");
  cmd->add_flag("--full", opts->full, "Print the full fit report instead of the brief one");
  cmd->callback([opts] { RunFit(*opts); });
}

CommandRegistrar reg("fit", Setup);

}  // namespace
}  // namespace trueaxis::cli
