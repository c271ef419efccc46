// trueaxis export: compensation tables for real CNC controllers
// (docs/export.md). Input: a fitted model (--model, --axis), a data-driven thermal
// model (--thermal-model, --channel, --axis, --range) or a measurement
// (--measurement). Output: LinuxCNC COMP_FILE, SINUMERIK LEC table, FANUC
// pitch-error tape, HEIDENHAIN .COM/.CMA, or plain CSV. `--read FILE` reads a
// table back and prints it as corrections (the round trip a user can check).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/export/csv_table.hpp"
#include "trueaxis/export/fanuc_table.hpp"
#include "trueaxis/export/heidenhain_states.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "trueaxis/export/resample.hpp"
#include "trueaxis/export/resample_axis_model.hpp"
#include "trueaxis/export/sinumerik_table.hpp"
#include "trueaxis/export/table_format.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/pitch/error_file.hpp"
#include "trueaxis/thermal/pso_bp_network.hpp"
#include "trueaxis/thermal/thermal_axis_model.hpp"
#include "trueaxis/thermal/thermal_model.hpp"

namespace trueaxis::cli {
namespace {

using namespace trueaxis::exporter;

constexpr const char* kCli = "command line";

struct ExportArgs {
  std::string model_path, measurement_path, pitch_path, axis, format, out, read;
  std::string thermal_model_path, channel;  // a `thermal fit` model and its error channel for --axis
  MeasurementInputOptions input;            // --measurement: a laser software's columns
  double start = ResampleOptions::kNaN, spacing = ResampleOptions::kNaN;
  int count = 0;
  std::string range;
  int max_points = 0;
  std::string mode = "auto";
  std::string sign;
  bool zero_at_reference = false;
  double reference_mm = ResampleOptions::kNaN;
  std::vector<std::string> temps;
  std::string coolant = "off";
  // linuxcnc
  int comp_file_type = 1;
  int joint = 0;
  // sinumerik
  std::string siemens_axis;
  int siemens_encoder = 0;
  bool siemens_thermal_in_table = false;
  // fanuc
  FanucOptions fanuc;
};

[[noreturn]] void Bad(const std::string& field, const std::string& message) {
  throw InputError(kCli, 0, field, message);
}

TableFormat FormatOf(const ExportArgs& a) {
  auto f = ParseTableFormat(a.format);
  if (!f) Bad("--format", fmt::format("'{}' is not one of linuxcnc, sinumerik, fanuc, heidenhain, csv", a.format));
  return *f;
}

ValueSign SignOf(const ExportArgs& a, TableFormat f) {
  if (a.sign.empty()) return ValueSign::kCorrection;
  if (a.sign != "correction" && a.sign != "error") Bad("--sign", fmt::format("'{}' is neither correction nor error", a.sign));
  if (f != TableFormat::kCsv && f != TableFormat::kHeidenhain)
    Bad("--sign", fmt::format("the {} format fixes its own sign (docs/export.md); --sign applies to csv and heidenhain",
                              TableFormatName(f)));
  return a.sign == "error" ? ValueSign::kError : ValueSign::kCorrection;
}

ThermalFreeze ThermalOf(const ExportArgs& a) {
  ThermalFreeze t;
  std::set<std::string> seen;
  for (const auto& s : a.temps) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0) Bad("--temp", fmt::format("'{}' is not NAME=DEGREES", s));
    const std::string name = s.substr(0, eq);
    auto v = ParseDouble(s.substr(eq + 1));
    if (!v || !std::isfinite(*v)) Bad("--temp", fmt::format("'{}' is not a temperature in °C", s.substr(eq + 1)));
    if (!seen.insert(name).second) Bad("--temp", fmt::format("sensor '{}' given twice", name));
    t.temperatures_c.emplace_back(name, *v);
  }
  auto c = ParseCoolantState(a.coolant);
  if (!c) Bad("--coolant", fmt::format("'{}' is not one of off, flood, mist, air", a.coolant));
  t.coolant = *c;
  return t;
}

ResampleOptions ResampleOf(const ExportArgs& a, TableFormat f) {
  ResampleOptions o;
  o.start_mm = a.start;
  o.spacing_mm = a.spacing;
  o.count = a.count;
  if (!a.range.empty()) {
    const auto colon = a.range.find(':');
    auto lo = colon == std::string::npos ? std::nullopt : ParseDouble(a.range.substr(0, colon));
    auto hi = colon == std::string::npos ? std::nullopt : ParseDouble(a.range.substr(colon + 1));
    if (!lo || !hi) Bad("--range", fmt::format("'{}' is not MIN:MAX in mm", a.range));
    for (double end : {*lo, *hi})
      if (auto why = ImplausiblePositionMm(end)) Bad("--range", fmt::format("'{}': {}", a.range, *why));
    o.range_min_mm = *lo;
    o.range_max_mm = *hi;
  }
  const int format_max = DefaultMaxPoints(f);
  o.max_points = a.max_points > 0 ? a.max_points : format_max;
  if ((f == TableFormat::kLinuxCnc || f == TableFormat::kHeidenhain) && o.max_points > format_max)
    Bad("--max-points", fmt::format("{} allows at most {} points per table", TableFormatName(f), format_max));
  if (a.mode == "auto") {
    o.bidirectional = SupportsBidirectional(f);
  } else if (a.mode == "bidirectional") {
    if (!SupportsBidirectional(f))
      Bad("--mode", fmt::format("{} tables hold one curve; use --mode unidirectional (mean curve + backlash)",
                                TableFormatName(f)));
    o.bidirectional = true;
  } else if (a.mode == "unidirectional") {
    o.bidirectional = false;
  } else {
    Bad("--mode", fmt::format("'{}' is not auto, bidirectional or unidirectional", a.mode));
  }
  if (f == TableFormat::kFanuc) {
    // One point number per interval and direction must fit in the axis's numbers: its own block
    // of the shared pool by default (FanucOptions::axes_sharing_pool), the whole pool when placed.
    const bool placed = a.fanuc.reference_point_number >= 0 || a.fanuc.reverse_first_number >= 0;
    const int numbers = (a.fanuc.max_point_number + 1) / (placed ? 1 : std::max(a.fanuc.axes_sharing_pool, 1));
    o.max_points = std::min(o.max_points, o.bidirectional ? numbers / 2 : numbers);
  }
  // FANUC tables are relative to the reference position by construction.
  o.zero_at_reference = a.zero_at_reference || f == TableFormat::kFanuc;
  o.reference_position_mm = a.reference_mm;
  o.reference_on_grid = f == TableFormat::kFanuc;  // FANUC counts its points from the reference
  o.thermal = ThermalOf(a);
  // SINUMERIK models the thermal line itself (temperature compensation), unless asked to freeze it.
  o.thermal_in_table = f != TableFormat::kSinumerik || a.siemens_thermal_in_table;
  std::string why;
  if (!o.IsValid(&why)) Bad(why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
  return o;
}

// An option whose "not given" value is NaN or 0 must not take that value when given: `--spacing nan`,
// `--count 0` or `--max-feed -1` silently became the default. Refused, naming the option.
void RefuseGivenValuesThatMeanDefault(const CLI::App& cmd, const ExportArgs& a) {
  const auto given = [&](const char* name) { return cmd.count(name) > 0; };
  for (const auto& [name, value] : {std::pair{"--start", a.start}, std::pair{"--reference-mm", a.reference_mm}})
    if (given(name))
      if (auto why = ImplausiblePositionMm(value)) Bad(name, *why);
  if (given("--spacing") && !(std::isfinite(a.spacing) && a.spacing > 0))
    Bad("--spacing", fmt::format("{} is not a positive number of mm", a.spacing));
  if (given("--count") && a.count < 2) Bad("--count", fmt::format("{}: a table needs at least 2 points", a.count));
  if (given("--max-points") && a.max_points < 2)
    Bad("--max-points", fmt::format("{}: a table needs at least 2 points", a.max_points));
  if (given("--max-feed") && !(std::isfinite(a.fanuc.max_feed_mm_per_min) && a.fanuc.max_feed_mm_per_min > 0))
    Bad("--max-feed", fmt::format("{} is not a positive feed in mm/min", a.fanuc.max_feed_mm_per_min));
}

std::string Upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string PrintTable(const CompensationTable& t) {
  std::string s = fmt::format("# axis {}: {} points, {}{}\n", t.axis, t.size(),
                              t.bidirectional ? "bidirectional" : "unidirectional",
                              t.bidirectional ? "" : fmt::format(", backlash {} um", FormatShortest(t.backlash_um)));
  if (t.thermal_tan_beta_um_per_mm != 0)
    s += fmt::format("# thermal line: tan_beta {} um/mm about {} mm (added below)\n",
                     FormatShortest(t.thermal_tan_beta_um_per_mm), FormatShortest(t.thermal_reference_mm));
  s += "position_mm,forward_correction_um,reverse_correction_um\n";
  for (double x : t.position_mm)
    s += fmt::format("{},{:.4f},{:.4f}\n", FormatShortest(x), AppliedCorrectionUm(t, x, Direction::kForward) + 0.0,
                     AppliedCorrectionUm(t, x, Direction::kReverse) + 0.0);
  return s;
}

void RunRead(const ExportArgs& a) {
  const TableFormat f = FormatOf(a);
  const std::string text = ReadTextFile(a.read);
  CompensationTable t;
  switch (f) {
    case TableFormat::kLinuxCnc: t = ReadLinuxCncCompFile(text, a.comp_file_type, a.read); break;
    case TableFormat::kSinumerik: t = ReadSinumerikEec(text, a.read); break;
    case TableFormat::kFanuc:
      t = ReadFanucPitchTape(text, a.fanuc.axis_number, a.fanuc.detection_unit_um,
                             std::isnan(a.reference_mm) ? 0.0 : a.reference_mm, a.read);
      break;
    case TableFormat::kCsv: t = ReadCsvTable(text, a.read); break;
    case TableFormat::kHeidenhain: {
      const ValueSign sign = SignOf(a, f);
      if (Upper(std::filesystem::path(a.read).extension().string()) == ".CMA") {
        const auto lines = ReadHeidenhainCma(text, a.axis.empty() ? "X" : a.axis, a.read);
        for (std::size_t i = 0; i < lines.size(); ++i)
          fmt::print("# CMA line {}: {} {} {}\n", i, lines[i].com_file, lines[i].active ? "ACTIVE" : "      ",
                     lines[i].description);
        for (const auto& l : lines)
          if (l.active) {
            const auto com = (std::filesystem::path(a.read).parent_path() / l.com_file).string();
            t = ReadHeidenhainCom(ReadTextFile(com), sign, com);
          }
      } else {
        t = ReadHeidenhainCom(text, sign, a.read);
      }
      break;
    }
  }
  // A CSV's "# axis:" and a .COM's axis column name the logical axis: one that is not --axis is another
  // axis's table. (A SINUMERIK file names the machine axis, X1, which --axis need not spell.)
  if ((f == TableFormat::kCsv || f == TableFormat::kHeidenhain) && !a.axis.empty() && !t.axis.empty() &&
      Upper(t.axis) != Upper(a.axis))
    throw InputError(a.read, 0, "axis", fmt::format("the table is for axis {}, not the --axis {} given", t.axis, a.axis));
  if (t.axis.empty()) t.axis = a.axis.empty() ? "?" : a.axis;
  fmt::print("{}", PrintTable(t));
}

// The positions a PSO-BP network that takes the position was trained on (its input scaling);
// unknown (NaN) for models that do not use the position.
AxisModelValidity TrainedPositions(const thermal::ThermalErrorModel& fitted, const std::string& channel) {
  AxisModelValidity v;
  const auto* network = dynamic_cast<const thermal::PsoBpNetworkModel*>(&fitted);
  if (!network) return v;
  const auto& names = network->Channels();
  for (std::size_t c = 0; c < names.size() && c < network->networks().size(); ++c) {
    const auto& n = network->networks()[c];
    if (names[c] == channel && n.uses_position && !n.input_min.empty()) {
      v.min_mm = n.input_min.back();
      v.max_mm = n.input_max.back();
    }
  }
  return v;
}

void RunExport(const ExportArgs& a) {
  const TableFormat f = FormatOf(a);
  if (a.out.empty()) Bad("--out", "required: the file to write");
  if (!a.model_path.empty() && !a.thermal_model_path.empty())
    Bad("--thermal-model", "give either --model (a `trueaxis fit` model file) or --thermal-model (a `trueaxis thermal fit` "
                           "model), not both");
  if (!a.model_path.empty() + !a.thermal_model_path.empty() + !a.measurement_path.empty() + !a.pitch_path.empty() != 1)
    Bad("--model", "give exactly one of --model (with --axis), --thermal-model (with --channel, --axis, --range), "
                   "--measurement or --pitch-file");
  if (!a.channel.empty() && a.thermal_model_path.empty()) Bad("--channel", "applies to --thermal-model only");
  if (a.input.Given() && a.measurement_path.empty()) Bad("--columns", "applies to --measurement only");
  const std::vector<std::string> inputs = {a.model_path, a.measurement_path, a.pitch_path, a.thermal_model_path,
                                          a.input.column_map};
  RefuseOutputOverInput(a.out, inputs, "--out");
  const ValueSign sign = SignOf(a, f);
  const ResampleOptions ro = ResampleOf(a, f);

  model::CompositeModel cm;
  const model::AxisModel* axis = nullptr;
  measure::Measurement meas;
  pitch::PitchErrorTable pitch_table;  // --pitch-file (docs/pitch-error-file.md)
  std::unique_ptr<thermal::ThermalAxisModel> thermal_axis;  // --thermal-model
  AxisModelValidity thermal_validity;  // a network taking the position: its training positions
  std::string thermal_kind;
  if (!a.pitch_path.empty()) {
    pitch_table = pitch::ReadPitchErrorFile(a.pitch_path);
    if (auto w = pitch::MeasuredRangeWarning(pitch_table, a.pitch_path)) fmt::print("warning: {}\n", *w);
  } else if (!a.thermal_model_path.empty()) {
    if (a.axis.empty()) Bad("--axis", "required with --thermal-model: the CNC axis the table is for");
    std::shared_ptr<const thermal::ThermalErrorModel> fitted = thermal::ReadThermalModelFile(a.thermal_model_path);
    if (a.channel.empty())
      Bad("--channel", fmt::format("required with --thermal-model: the model's error channel for axis {} (it has: {})",
                                   a.axis, fmt::join(fitted->Channels(), ", ")));
    if (a.coolant != "off")
      Bad("--coolant", "a data-driven thermal model has no coolant gains; its table is the same for every coolant state");
    thermal_axis = std::make_unique<thermal::ThermalAxisModel>(fitted, a.channel, a.axis, a.thermal_model_path);
    thermal_validity = TrainedPositions(*fitted, a.channel);
    thermal_kind = fitted->Kind();
  } else if (!a.model_path.empty()) {
    if (a.axis.empty()) Bad("--axis", "required with --model");
    cm = model::ReadModelFile(a.model_path);
    axis = cm.FindAxis(a.axis);
    if (!axis) {
      std::string known;
      for (const auto& ax : cm.axes) known += (known.empty() ? "" : ", ") + ax.axis;
      Bad("--axis", fmt::format("the model has no axis '{}' (it has: {})", a.axis, known));
    }
  } else {
    meas = a.input.Read(a.measurement_path);
  }
  auto resample = [&](const ResampleOptions& o) {
    if (!a.pitch_path.empty()) return pitch::ResamplePitchTable(pitch_table, o, a.pitch_path);
    if (thermal_axis) return ResampleAxisErrorModel(*thermal_axis, o, a.thermal_model_path, thermal_validity);
    return axis ? ResampleModel(*axis, o, a.model_path) : ResampleMeasurement(meas, o);
  };
  ResampleResult rr = resample(ro);
  if (!axis && !a.axis.empty()) rr.table.axis = a.axis;
  if (rr.table.axis.empty()) rr.table.axis = "X";
  fmt::print("{}\n", rr.BriefReport());
  if (thermal_axis) {
    fmt::print("note: {} thermal model, channel {} on axis {}, frozen at the given temperatures{}\n", thermal_kind,
               a.channel, a.axis,
               thermal_axis->HasDynamics() ? " (model dynamics at start-up: lagged inputs settled at them, a hysteresis "
                                             "model's all-data prediction)"
                                           : "");
    if (IsConstantAlongAxis(rr.table) && rr.zero_shift_um != 0)
      fmt::print("warning: the model predicts the same error at every position, so zeroing at the reference removes "
                 "all of it ({:.4f} um): this table compensates nothing; a position-independent offset belongs in a "
                 "work or tool offset\n", rr.zero_shift_um);
    else if (IsConstantAlongAxis(rr.table))
      fmt::print("note: the model predicts the same error at every position (channel {} does not use the position): "
                 "the table is one offset\n", a.channel);
  }
  if (!a.pitch_path.empty())
    for (const auto& p : rr.table.provenance)
      if (p.rfind("resampled", 0) == 0 || p.rfind("measured range", 0) == 0) fmt::print("note: {}\n", p);
  if (a.mode == "auto" && !SupportsBidirectional(f))
    fmt::print("note: {} holds one curve per axis: exported unidirectional (mean curve + backlash)\n", TableFormatName(f));
  if (f == TableFormat::kSinumerik && !a.zero_at_reference) {
    const double at_ref = SinumerikValueAtReferenceUm(rr.table);
    if (std::abs(at_ref) > 0.5)  // false for NaN (reference outside the table)
      fmt::print("note: the LEC value at the reference point {} mm is {:.2f} um; Siemens recommends 0 there "
                 "(no jump when LEC activates after referencing): consider --zero-at-reference\n",
                 FormatShortest(rr.table.reference_position_mm), at_ref);
  }
  if (f == TableFormat::kFanuc && !a.zero_at_reference)
    fmt::print("note: FANUC tables are relative to the reference position: zeroed there (shift {:.4f} um)\n",
               rr.zero_shift_um);

  switch (f) {
    case TableFormat::kLinuxCnc: {
      LinuxCncOptions o;
      o.comp_file_type = a.comp_file_type;
      o.joint = a.joint;
      o.comp_file_name = std::filesystem::path(a.out).filename().string();
      const std::string text = WriteLinuxCncCompFile(rr.table, o, kCli);
      WriteTextFile(a.out, text);
      fmt::print("wrote {}\npaste into the INI file:\n{}", a.out, LinuxCncIniSnippet(rr.table, o));
      break;
    }
    case TableFormat::kSinumerik: {
      SinumerikOptions o;
      o.axis_name = a.siemens_axis.empty() ? a.axis.empty() ? rr.table.axis + "1" : a.axis + "1" : a.siemens_axis;
      o.encoder = a.siemens_encoder;
      const std::string text = WriteSinumerikEec(rr.table, o, kCli);
      WriteTextFile(a.out, text);
      fmt::print("wrote {}\nset these machine/setting data (also in the file as comments):\n{}", a.out,
                 SinumerikMachineData(rr.table, o));
      break;
    }
    case TableFormat::kFanuc: {
      const FanucResult res = WriteFanucPitchTape(rr.table, a.fanuc, kCli);
      WriteTextFile(a.out, res.tape);
      fmt::print("wrote {}\n{}", a.out, res.Instructions());
      break;
    }
    case TableFormat::kCsv: {
      WriteTextFile(a.out, WriteCsvTable(rr.table, sign, kCli));
      fmt::print("wrote {}\n", a.out);
      break;
    }
    case TableFormat::kHeidenhain: {
      const std::filesystem::path out(a.out);
      if (Upper(out.extension().string()) != ".CMA") Bad("--out", "for heidenhain give the .CMA file; the .COM files go next to it");
      std::vector<HeidenhainState> states;
      if (thermal_axis) {
        states.push_back({"THERMAL", "thermal model frozen at the given temperatures", rr.table, true});
      } else if (axis) {
        states = HeidenhainModelStates(*axis, ro, a.model_path);
        if (std::none_of(states.begin(), states.end(), [](const auto& s) { return s.active; }))
          Bad("--coolant", fmt::format("the model has no thermal gains for coolant '{}'", CoolantStateName(ro.thermal.coolant)));
      } else {
        states.push_back({"COLD", "as measured", rr.table, true});
      }
      const auto files = WriteHeidenhainSet(states, rr.table.axis, out.filename().string(), sign, kCli);
      for (const auto& file : files) RefuseOutputOverInput((out.parent_path() / file.file_name).string(), inputs, "--out");
      for (const auto& file : files) {
        const auto path = (out.parent_path() / file.file_name).string();
        WriteTextFile(path, file.text);
        fmt::print("wrote {}\n", path);
      }
      fmt::print("{} lines; switch lines by soft key or PLC; MP_backLash must be 0 when BACKLASH columns are used\n",
                 states.size());
      break;
    }
  }
}

void Setup(CLI::App& app) {
  auto a = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand("export", "Write (or --read back) a compensation table for a CNC controller");
  cmd->add_option("--model", a->model_path, "fitted model JSON (docs/model-file.md)");
  cmd->add_option("--measurement", a->measurement_path,
                  "measurement (canonical CSV, ecmc .dat or a mapped laser export): per-target mean deviations per "
                  "direction");
  AddMeasurementInputOptions(cmd, a->input);
  cmd->add_option("--pitch-file", a->pitch_path, "pitch error file (once per lead, docs/pitch-error-file.md)");
  cmd->add_option("--thermal-model", a->thermal_model_path,
                  "data-driven thermal model from `trueaxis thermal fit` (needs --channel, --axis, --range, --temp)");
  cmd->add_option("--channel", a->channel, "the thermal model's error channel that is --axis's error (as run's thermal_channels)");
  cmd->add_option("--axis", a->axis, "axis name in the model (X, Y, Z, ...)");
  cmd->add_option("--format", a->format, "linuxcnc | sinumerik | fanuc | heidenhain | csv")->required();
  cmd->add_option("--out", a->out, "file to write (heidenhain: the .CMA; .COM files go next to it)");
  cmd->add_option("--read", a->read, "read this table back and print it as corrections (um)");
  cmd->add_option("--start", a->start, "first table position, mm (default: derived, aligned on the reference)");
  cmd->add_option("--spacing", a->spacing, "distance between points, mm (default: smallest 1-2-5 step that fits)");
  cmd->add_option("--count", a->count, "number of points (default: derived)");
  cmd->add_option("--range", a->range, "MIN:MAX axis range to cover, mm (default: where the model is valid; required with --thermal-model)");
  cmd->add_option("--max-points", a->max_points, "point limit (default: the format's)");
  cmd->add_option("--mode", a->mode, "auto | bidirectional | unidirectional (mean curve + one backlash value)");
  cmd->add_option("--sign", a->sign, "csv/heidenhain: correction (default) or error");
  cmd->add_flag("--zero-at-reference", a->zero_at_reference, "shift the table to 0 at the reference point");
  cmd->add_option("--reference-mm", a->reference_mm, "reference point, mm (default: the model's Px; --thermal-model: the --range minimum; fanuc --read: 0)");
  cmd->add_option("--temp", a->temps, "NAME=DEGREES: freeze the thermal part at this sensor temperature (repeat, or "
                  "comma separated as predict takes them)")
      ->delimiter(',')
      ->allow_extra_args(false);
  cmd->add_option("--coolant", a->coolant, "coolant state for the frozen thermal part: off | flood | mist | air");
  cmd->add_option("--comp-file-type", a->comp_file_type, "linuxcnc COMP_FILE_TYPE 0 (actual) or 1 (trim, default)");
  cmd->add_option("--joint", a->joint, "linuxcnc [JOINT_n] for the INI lines");
  cmd->add_option("--siemens-axis", a->siemens_axis, "sinumerik machine axis name (default: <axis>1)");
  cmd->add_option("--siemens-encoder", a->siemens_encoder, "sinumerik measuring system 0 or 1");
  cmd->add_flag("--siemens-thermal-in-table", a->siemens_thermal_in_table,
                "sinumerik: freeze the thermal part into the LEC values instead of TEMP_COMP settings");
  cmd->add_option("--fanuc-axis", a->fanuc.axis_number, "fanuc controlled axis number (A<n>)");
  cmd->add_option("--detection-unit-um", a->fanuc.detection_unit_um, "fanuc detection unit, um (default 1)");
  cmd->add_option("--fanuc-magnification", a->fanuc.magnification, "3623, 1..100 (default: smallest that fits)");
  cmd->add_option("--fanuc-point-limit", a->fanuc.point_limit, "largest |value| per point (default 7)");
  cmd->add_option("--fanuc-reference-number", a->fanuc.reference_point_number, "3620 (default: derived)");
  cmd->add_option("--fanuc-reverse-number", a->fanuc.reverse_first_number, "3626 (default: after the forward block)");
  cmd->add_option("--fanuc-max-point", a->fanuc.max_point_number, "highest compensation point number (default 1023)");
  cmd->add_option("--fanuc-axes", a->fanuc.axes_sharing_pool,
                  "axes sharing the point numbers: each gets its own block by default (default 4)");
  cmd->add_option("--max-feed", a->fanuc.max_feed_mm_per_min, "fanuc: max feedrate mm/min; interval >= feed/7500");
  cmd->callback([a, cmd] {
    RefuseGivenValuesThatMeanDefault(*cmd, *a);
    if (!a->read.empty()) RunRead(*a);
    else RunExport(*a);
  });
}

static CommandRegistrar reg("export", Setup);

}  // namespace
}  // namespace trueaxis::cli
