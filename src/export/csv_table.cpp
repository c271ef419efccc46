#include "trueaxis/export/csv_table.hpp"

#include <cmath>
#include <optional>
#include <vector>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

std::string WriteCsvTable(const CompensationTable& t, ValueSign sign, const std::string& source) {
  ValidateTable(t, source);
  if (t.thermal_tan_beta_um_per_mm != 0)
    throw InputError(source, 0, "thermal", "the CSV table holds no temperature line; freeze the thermal part into it");
  const double k = SignFactor(sign);
  const char* word = sign == ValueSign::kCorrection ? "correction" : "error";
  std::string out = "# trueaxis compensation table\n";
  out += fmt::format("# axis: {}\n# sign: {}\n", t.axis, word);
  out += fmt::format("# mode: {}\n", t.bidirectional ? "bidirectional" : "unidirectional");
  if (!t.bidirectional) out += fmt::format("# backlash_um: {}\n", FormatShortest(t.backlash_um));
  if (!std::isnan(t.reference_position_mm))
    out += fmt::format("# reference_position_mm: {}\n", FormatShortest(t.reference_position_mm));
  for (const auto& p : t.provenance) out += "# provenance: " + p + "\n";
  out += fmt::format("position_mm,forward_{0}_um,reverse_{0}_um\n", word);
  for (std::size_t i = 0; i < t.size(); ++i)
    out += fmt::format("{},{},{}\n", FormatShortest(t.position_mm[i]), FormatShortest(k * t.forward_um[i] + 0.0),
                       FormatShortest(k * t.reverse_um[i] + 0.0));
  return out;
}

CompensationTable ReadCsvTable(std::string_view text, const std::string& source) {
  CompensationTable t;
  std::optional<ValueSign> sign;
  bool header_seen = false;
  int line_no = 0;
  std::string mode = "bidirectional";
  std::optional<ValueSign> commented_sign;  // "# sign:", which must agree with the header
  int sign_line = 0;
  std::vector<int> point_lines;
  LineCursor cursor(text);
  while (cursor.Next()) {
    line_no = cursor.number();
    std::string_view line = cursor.line();
    if (line.empty()) continue;
    if (line[0] == '#') {
      const auto colon = line.find(':');
      if (colon == std::string_view::npos) continue;
      const std::string key(Trim(line.substr(1, colon - 1)));
      const std::string_view value = Trim(line.substr(colon + 1));
      if (key == "axis") t.axis = std::string(value);
      else if (key == "sign") {
        if (value != "correction" && value != "error")
          throw InputError(source, line_no, "sign", fmt::format("'{}' is neither correction nor error", value));
        commented_sign = value == "correction" ? ValueSign::kCorrection : ValueSign::kError;
        sign_line = line_no;
      } else if (key == "mode") {
        if (value != "bidirectional" && value != "unidirectional")
          throw InputError(source, line_no, "mode", fmt::format("'{}' is neither bidirectional nor unidirectional", value));
        mode = std::string(value);
      } else if (key == "backlash_um" || key == "reference_position_mm") {
        auto d = ParseDouble(value);
        if (!d) throw InputError(source, line_no, key, fmt::format("'{}' is not a number", value));
        (key == "backlash_um" ? t.backlash_um : t.reference_position_mm) = *d;
      } else if (key == "provenance") t.provenance.emplace_back(value);
      continue;
    }
    if (!header_seen) {
      if (line == "position_mm,forward_correction_um,reverse_correction_um") sign = ValueSign::kCorrection;
      else if (line == "position_mm,forward_error_um,reverse_error_um") sign = ValueSign::kError;
      else
        throw InputError(source, line_no, "header",
                         fmt::format("expected 'position_mm,forward_correction_um,reverse_correction_um' "
                                     "(or the _error_um form), found '{}'", line));
      header_seen = true;
      if (commented_sign && *commented_sign != *sign)
        throw InputError(source, line_no, "header",
                         fmt::format("the header gives {} values but line {} says '# sign: {}'",
                                     *sign == ValueSign::kCorrection ? "correction" : "error", sign_line,
                                     *commented_sign == ValueSign::kCorrection ? "correction" : "error"));
      continue;
    }
    std::vector<std::string_view> f;
    std::size_t a = 0;
    while (true) {
      const auto c = line.find(',', a);
      f.push_back(line.substr(a, c == std::string_view::npos ? std::string_view::npos : c - a));
      if (c == std::string_view::npos) break;
      a = c + 1;
    }
    if (f.size() != 3) throw InputError(source, line_no, "row", fmt::format("expected 3 fields, found {}", f.size()));
    static const char* kNames[3] = {"position_mm", "forward", "reverse"};
    double v[3];
    for (int k = 0; k < 3; ++k) {
      auto d = ParseDouble(f[k]);
      if (!d || !std::isfinite(*d)) throw InputError(source, line_no, kNames[k], fmt::format("'{}' is not a number", f[k]));
      v[k] = *d;
    }
    if (!t.position_mm.empty() && !(v[0] > t.position_mm.back()))
      throw InputError(source, line_no, "position_mm",
                       fmt::format("positions must be strictly ascending ({} follows {})", v[0], t.position_mm.back()));
    const double k = SignFactor(*sign);
    t.position_mm.push_back(v[0]);
    point_lines.push_back(line_no);
    t.forward_um.push_back(k * v[1]);
    t.reverse_um.push_back(k * v[2]);
  }
  if (!header_seen) throw InputError(source, 0, "header", "no column header line found");
  t.bidirectional = mode == "bidirectional";
  if (t.bidirectional) t.backlash_um = 0;
  ValidateReadTable(t, source, point_lines);
  if (!t.bidirectional)
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t.forward_um[i] != t.reverse_um[i])
        throw InputError(source, 0, "mode",
                         fmt::format("unidirectional table but forward and reverse differ at {} mm", t.position_mm[i]));
  return t;
}

}  // namespace trueaxis::exporter
