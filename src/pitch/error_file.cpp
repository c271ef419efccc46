#include "trueaxis/pitch/error_file.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"

namespace trueaxis::pitch {

namespace {

constexpr const char* kHeader = "position_mm,error_up_um,error_down_um";
constexpr double kGridTolMm = 1e-3;

std::string Num(double v) { return FormatShortest(std::round(v * 1e6) / 1e6); }

}  // namespace

std::string FormatPitchErrorFile(const PitchErrorTable& t) {
  ValidatePitchTable(t, "pitch error table");
  std::string s = "# trueaxis pitch error file (docs/pitch-error-file.md)\n";
  s += fmt::format("# format: {}\n", kPitchErrorFormat);
  s += fmt::format("# axis: {}\n", t.axis);
  s += fmt::format("# lead_mm: {}\n", FormatShortest(t.lead_mm));
  s += fmt::format("# samples_per_lead: {}\n", t.samples_per_lead);
  s += fmt::format("# reference_mm: {}\n", FormatShortest(t.reference_mm));
  if (t.HasMeasuredRange()) {  // the range the table vouches for: beyond it the end values are held
    s += fmt::format("# measured_from_mm: {}\n", Num(t.measured_from_mm));
    s += fmt::format("# measured_to_mm: {}\n", Num(t.measured_to_mm));
  }
  s += "# sign: error (actual - commanded, um); the CNC adds the correction -error\n";
  for (const auto& p : t.provenance) s += fmt::format("# provenance: {}\n", p);
  s += kHeader;
  s += '\n';
  for (std::size_t i = 0; i < t.size(); ++i)
    s += fmt::format("{},{:.4f},{:.4f}\n", Num(t.position_mm[i]), t.error_up_um[i] + 0.0, t.error_down_um[i] + 0.0);
  return s;
}

void WritePitchErrorFile(const PitchErrorTable& table, const std::string& path) {
  WriteTextFile(path, FormatPitchErrorFile(table));
}

PitchErrorTable ParsePitchErrorFile(std::string_view raw, const std::string& source) {
  const std::string text = CanonicalCsv(raw);
  PitchErrorTable t;
  std::optional<double> lead, reference;
  std::optional<long long> per_lead;
  bool have_axis = false, header_seen = false;
  int lead_line = 0, range_line = 0;
  LineCursor cur(text);
  auto number = [&](std::string_view field_text, const char* field) {
    auto v = ParseDouble(field_text);
    if (!v || !std::isfinite(*v))
      throw InputError(source, cur.number(), field, fmt::format("'{}' is not a number", field_text));
    return *v;
  };
  while (cur.Next()) {
    const std::string_view line = cur.line();
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (header_seen) continue;  // comments among the rows are allowed
      auto kv = ParseMetadataComment(line);
      if (!kv) continue;
      const auto [key, value] = *kv;
      if (key == "format") {
        if (value != kPitchErrorFormat)
          throw InputError(source, cur.number(), "format", fmt::format("'{}' is not {} (the version this trueaxis reads)",
                                                                       value, kPitchErrorFormat));
      } else if (key == "axis") {
        if (value.empty()) throw InputError(source, cur.number(), "axis", "empty");
        t.axis = std::string(value);
        have_axis = true;
      } else if (key == "lead_mm") {
        lead = number(value, "lead_mm");
        lead_line = cur.number();
        if (!(*lead >= 0.5 && *lead <= 200))
          throw InputError(source, cur.number(), "lead_mm", fmt::format("{} mm is outside 0.5…200 mm", value));
      } else if (key == "samples_per_lead") {
        per_lead = ParseInt(value);
        if (!per_lead || *per_lead < 1 || *per_lead > 64)
          throw InputError(source, cur.number(), "samples_per_lead", fmt::format("'{}' is not a whole number 1…64", value));
      } else if (key == "reference_mm") {
        reference = number(value, "reference_mm");
        if (auto why = ImplausiblePositionMm(*reference)) throw InputError(source, cur.number(), "reference_mm", *why);
      } else if (key == "measured_from_mm" || key == "measured_to_mm") {
        const double v = number(value, key == "measured_from_mm" ? "measured_from_mm" : "measured_to_mm");
        if (auto why = ImplausiblePositionMm(v)) throw InputError(source, cur.number(), std::string(key), *why);
        (key == "measured_from_mm" ? t.measured_from_mm : t.measured_to_mm) = v;
        range_line = cur.number();
      } else if (key == "sign") {
        if (value.substr(0, 5) != "error")
          throw InputError(source, cur.number(), "sign",
                           fmt::format("'{}': a pitch error file holds errors (actual - commanded)", value));
      } else if (key == "provenance") {
        t.provenance.emplace_back(value);
      }
      continue;
    }
    if (!header_seen) {
      if (line != kHeader)
        throw InputError(source, cur.number(), "header", fmt::format("'{}' is not '{}'", line, kHeader));
      header_seen = true;
      if (!have_axis) throw InputError(source, cur.number(), "axis", "missing '# axis:' line before the header");
      if (!lead) throw InputError(source, cur.number(), "lead_mm", "missing '# lead_mm:' line before the header");
      t.lead_mm = *lead;
      t.samples_per_lead = per_lead ? static_cast<int>(*per_lead) : 1;
      continue;
    }
    const auto fields = SplitCsvFields(line);
    if (fields.size() != 3)
      throw InputError(source, cur.number(), fields.size() < 3 ? (fields.size() < 2 ? "error_up_um" : "error_down_um") : "row",
                       fmt::format("{} fields; a row is position_mm,error_up_um,error_down_um", fields.size()));
    const double x = number(fields[0], "position_mm");
    const double up = number(fields[1], "error_up_um");
    const double down = number(fields[2], "error_down_um");
    if (auto why = ImplausiblePositionMm(x)) throw InputError(source, cur.number(), "position_mm", *why);
    if (auto why = ImplausibleDeviationUm(up)) throw InputError(source, cur.number(), "error_up_um", *why);
    if (auto why = ImplausibleDeviationUm(down)) throw InputError(source, cur.number(), "error_down_um", *why);
    const double spacing = t.SpacingMm();
    if (t.position_mm.empty()) {
      if (!reference) reference = x;
      const double k = (x - *reference) / spacing;
      if (std::abs(k - std::round(k)) * spacing > kGridTolMm)
        throw InputError(source, cur.number(), "position_mm",
                         fmt::format("{} mm is not on the grid {} + k·{} mm (reference_mm, lead_mm / samples_per_lead)",
                                     Num(x), Num(*reference), Num(spacing)));
    } else if (std::abs(x - t.position_mm.back() - spacing) > kGridTolMm) {
      throw InputError(source, cur.number(), "position_mm",
                       fmt::format("{} mm follows {} mm: rows must ascend every {} mm (lead_mm {} from line {} / "
                                   "samples_per_lead {}), none missing",
                                   Num(x), Num(t.position_mm.back()), Num(spacing), Num(t.lead_mm), lead_line,
                                   t.samples_per_lead));
    }
    t.position_mm.push_back(x);
    t.error_up_um.push_back(up);
    t.error_down_um.push_back(down);
  }
  if (!header_seen) throw InputError(source, cur.number(), "header", fmt::format("missing '{}'", kHeader));
  if (t.size() < 2)
    throw InputError(source, cur.number(), "position_mm", fmt::format("{} rows; a table needs at least 2", t.size()));
  t.reference_mm = *reference;
  try {
    ValidatePitchTable(t, source);
  } catch (const InputError& e) {  // the range is the one check the rows cannot place: name its line
    if (range_line == 0 || (e.field() != "measured_from_mm" && e.field() != "measured_to_mm")) throw;
    throw InputError(source, range_line, e.field(), e.message());
  }
  return t;
}

PitchErrorTable ReadPitchErrorFile(const std::string& path) { return ParsePitchErrorFile(ReadTextFile(path), path); }

}  // namespace trueaxis::pitch
