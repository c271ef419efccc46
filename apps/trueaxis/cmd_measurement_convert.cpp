// trueaxis measurement convert IN --out OUT.csv [--columns …|--column-map FILE.toml]
//                              [--axis X] [--state cold] [--coolant flood] [--meta key=value]…
// Writes any measurement trueaxis reads (ecmc .dat, a laser software's CSV through a column
// mapping, the canonical CSV itself) as the canonical CSV (docs/formats.md), metadata kept, so the
// user can look at and keep the file every command reads alike. The written text is read back and
// must give the same measurement, else nothing is written.
#include <cmath>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "command.hpp"
#include "measurement_input.hpp"
#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"

namespace trueaxis::cli {
namespace {

struct ConvertOptions {
  std::string in, out, axis, state, coolant;
  std::vector<std::string> meta;  // key=value
  MeasurementInputOptions input;
};

// Sets metadata `key` from an option; a file that says otherwise is refused (which is right is the
// user's call, never a silent overwrite).
void SetFromOption(measure::Measurement& m, const std::string& key, const std::string& value, const std::string& option) {
  if (auto own = m.Meta(key); own && std::string(Trim(*own)) != value)
    throw InputError(m.source, m.MetaLine(key), key,
                     fmt::format("the file says '{}', {} says '{}': correct one of them", *own, option, value));
  m.SetMeta(key, value);
}

// Whether `a` and `b` are the same measurement, value for value (NaN temperatures alike).
bool SameMeasurement(const measure::Measurement& a, const measure::Measurement& b) {
  if (a.metadata != b.metadata || a.sensor_names != b.sensor_names || a.has_time != b.has_time ||
      a.points.size() != b.points.size())
    return false;
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    const auto &p = a.points[i], &q = b.points[i];
    if (p.run != q.run || p.direction != q.direction || p.target_mm != q.target_mm || p.deviation_um != q.deviation_um ||
        (a.has_time && p.time_s.value_or(0) != q.time_s.value_or(0)) || p.temperatures_c.size() != q.temperatures_c.size())
      return false;
    for (std::size_t k = 0; k < p.temperatures_c.size(); ++k)
      if (p.temperatures_c[k] != q.temperatures_c[k] && !(std::isnan(p.temperatures_c[k]) && std::isnan(q.temperatures_c[k])))
        return false;
  }
  return true;
}

void RunConvert(const ConvertOptions& o) {
  RefuseOutputOverInput(o.out, {o.in, o.input.column_map}, "--out");
  RefuseUnwritableOutputFile(o.out, "--out");
  const auto read = o.input.Resolve();
  const std::string text = ReadTextFile(o.in);
  const auto format = measure::DetectMeasurementFormat(o.in, text, read);
  measure::Measurement m = measure::ParseMeasurement(text, o.in, read);
  if (!o.axis.empty()) SetFromOption(m, "axis", o.axis, "--axis");
  if (!o.state.empty()) SetFromOption(m, "state", o.state, "--state");
  if (!o.coolant.empty()) {
    if (!ParseCoolantState(LowerAscii(o.coolant)))
      throw InputError("command line", 0, "--coolant",
                       fmt::format("unknown coolant state '{}' (expected off, flood, mist or air)", o.coolant));
    SetFromOption(m, "coolant", o.coolant, "--coolant");
  }
  for (const auto& kv : o.meta) {
    const auto eq = kv.find('=');
    const std::string key(eq == std::string::npos ? "" : Trim(std::string_view(kv).substr(0, eq)));
    if (key.empty() || key.find_first_of(":#\n") != std::string::npos)
      throw InputError("command line", 0, "--meta", fmt::format("'{}' is not key=value (a key without ':' or '#')", kv));
    SetFromOption(m, key, std::string(Trim(std::string_view(kv).substr(eq + 1))), "--meta");
  }
  if (format != measure::MeasurementFormat::kCanonicalCsv && !m.Meta("converted_from"))
    m.SetMeta("converted_from", o.in);
  const std::string csv = measure::FormatMeasurementCsv(m);
  // What is written must read back as this measurement: the canonical file is the one kept.
  if (!SameMeasurement(m, measure::ParseMeasurementCsv(csv, o.out)))
    throw std::runtime_error(fmt::format("{}: the canonical CSV would not read back as the same measurement; nothing "
                                         "written", o.in));
  WriteTextFile(o.out, csv);
  fmt::print("{} ({}): {} points, {} runs, {} targets{}{} -> {}\n", o.in, measure::MeasurementFormatName(format),
             m.points.size(), m.Runs().size(), m.Targets().size(),
             m.sensor_names.empty() ? "" : fmt::format(", temperatures {}", fmt::join(m.sensor_names, ", ")),
             m.has_time ? ", time" : "", o.out);
  if (auto why = measure::DeviationUnitWarning(m)) fmt::print(stderr, "warning: {}: {}\n", o.in, *why);
  if (!m.Meta("axis")) fmt::print("note: no axis named: give --axis (fit and predict need it)\n");
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<ConvertOptions>();
  CLI::App* group = CommandGroup(app, "measurement", "Laser measurement files (convert to the canonical CSV)");
  CLI::App* cmd = group->add_subcommand(
      "convert", "Write a measurement (ecmc .dat, a laser software's CSV with --columns, a canonical CSV) as the "
                 "canonical CSV, metadata kept");
  cmd->add_option("file", o->in, "measurement file to convert")->required()->check(CLI::ExistingFile);
  cmd->add_option("--out", o->out, "canonical CSV to write (docs/formats.md)")->required();
  AddMeasurementInputOptions(cmd, o->input);
  cmd->add_option("--axis", o->axis, "axis name written as '# axis:' (refused if the file names another)");
  cmd->add_option("--state", o->state, "thermal state written as '# state:' (cold, heated-1, ambient-24, …; for fit)");
  cmd->add_option("--coolant", o->coolant, "coolant state written as '# coolant:' (off, flood, mist, air)");
  cmd->add_option("--meta", o->meta, "more metadata as key=value (machine, operator, date, lead_mm, …)");
  cmd->callback([o] { RunConvert(*o); });
}

static CommandRegistrar reg("measurement_convert", Setup);

}  // namespace
}  // namespace trueaxis::cli
