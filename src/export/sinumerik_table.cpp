#include "trueaxis/export/sinumerik_table.hpp"

#include <cmath>
#include <map>
#include <optional>
#include <regex>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

bool SinumerikOptions::IsValid(std::string* why) const {
  static const std::regex kAxis("[A-Z][A-Z0-9_]{0,7}");
  if (!std::regex_match(axis_name, kAxis)) {
    if (why) *why = "--siemens-axis: machine axis name like X1 (letters/digits, starts with a letter)";
    return false;
  }
  if (encoder != 0 && encoder != 1) {
    if (why) *why = "--siemens-encoder: measuring system 0 or 1";
    return false;
  }
  return true;
}

namespace {
std::string Mm(double v) { return fmt::format("{:.6f}", v + 0.0); }
}  // namespace

std::string SinumerikMachineData(const CompensationTable& t, const SinumerikOptions& o) {
  const std::string& ax = o.axis_name;
  std::string s;
  s += fmt::format("MD38000 $MA_MM_ENC_COMP_MAX_POINTS[{},{}]={}  ; at least the number of points (memory, POWER ON)\n",
                   o.encoder, ax, t.size());
  s += fmt::format("MD32700 $MA_ENC_COMP_ENABLE[{},{}]=1  ; enable LEC (set 0 while loading the table)\n", o.encoder, ax);
  s += fmt::format("MD32450 $MA_BACKLASH[{},{}]={}  ; backlash, mm\n", o.encoder, ax, Mm(t.backlash_um / 1000.0));
  s += fmt::format("MD32750 $MA_TEMP_COMP_TYPE[{}]={}  ; bit1 = position-dependent temperature compensation\n", ax,
                   t.thermal_tan_beta_um_per_mm != 0 ? 2 : 0);
  s += fmt::format("SD43900 $SA_TEMP_COMP_ABS_VALUE[{}]={}  ; mm\n", ax, Mm(0));
  s += fmt::format("SD43910 $SA_TEMP_COMP_SLOPE[{}]={:.9f}  ; = -tan_beta (trueaxis um/mm) / 1000\n", ax,
                   -t.thermal_tan_beta_um_per_mm / 1000.0 + 0.0);
  s += fmt::format("SD43920 $SA_TEMP_COMP_REF_POSITION[{}]={}  ; = Px, mm\n", ax, Mm(t.thermal_reference_mm));
  return s;
}

std::string WriteSinumerikEec(const CompensationTable& t, const SinumerikOptions& o, const std::string& source) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError(source, 0, why.substr(0, why.find(':')), why.substr(why.find(':') + 2));
  ValidateTable(t, source);
  if (t.bidirectional)
    throw InputError(source, 0, "--mode",
                     "a SINUMERIK LEC table holds one curve per measuring system; export --mode unidirectional "
                     "(mean curve + MD32450 backlash)");
  if (t.size() < 2) throw InputError(source, 0, "--count", "a LEC table needs at least 2 points");
  const double step = t.UniformSpacingMm();
  if (std::isnan(step))
    throw InputError(source, 0, "--spacing",
                     "SINUMERIK LEC tables are equidistant ($AA_ENC_COMP_STEP); give --spacing to resample");
  const std::string& ax = o.axis_name;
  std::string out = "%_N_AX_EEC_INI\nCHANDATA(1)\n";
  out += fmt::format("; trueaxis LEC table axis {} ({}): values = ERROR (actual - commanded) in mm\n", t.axis, ax);
  for (const auto& p : t.provenance) out += "; " + p + "\n";
  out += "; machine/setting data to set (not assigned by this file):\n";
  std::string md = SinumerikMachineData(t, o);
  std::size_t a = 0;
  while (a < md.size()) {
    const auto nl = md.find('\n', a);
    out += ";   " + md.substr(a, nl - a) + "\n";
    a = nl + 1;
  }
  for (std::size_t i = 0; i < t.size(); ++i)
    out += fmt::format("$AA_ENC_COMP[{},{},{}]={}\n", o.encoder, i, ax, Mm(-t.forward_um[i] / 1000.0));
  out += fmt::format("$AA_ENC_COMP_STEP[{},{}]={}\n", o.encoder, ax, Mm(step));
  out += fmt::format("$AA_ENC_COMP_MIN[{},{}]={}\n", o.encoder, ax, Mm(t.position_mm.front()));
  out += fmt::format("$AA_ENC_COMP_MAX[{},{}]={}\n", o.encoder, ax, Mm(t.position_mm.back()));
  out += fmt::format("$AA_ENC_COMP_IS_MODULO[{},{}]=0\n", o.encoder, ax);
  out += "M17\n";
  return out;
}

CompensationTable ReadSinumerikEec(std::string_view text, const std::string& source) {
  static const std::regex kComp(R"(\$AA_ENC_COMP\[\s*(\d+)\s*,\s*(\d+)\s*,\s*([A-Z][A-Z0-9_]*)\s*\]\s*=\s*(\S+))");
  static const std::regex kParam(R"(\$AA_ENC_COMP_(STEP|MIN|MAX|IS_MODULO)\[\s*(\d+)\s*,\s*([A-Z][A-Z0-9_]*)\s*\]\s*=\s*(\S+))");
  static const std::regex kData(R"(\$(MA_BACKLASH|SA_TEMP_COMP_ABS_VALUE|SA_TEMP_COMP_SLOPE|SA_TEMP_COMP_REF_POSITION)\[[^\]]*\]\s*=\s*([-+0-9.eE]+))");
  std::map<long long, double> values;
  std::map<long long, int> value_line;
  std::map<std::string, double> params;
  std::map<std::string, double> data;
  std::optional<std::string> axis;
  bool header = false, end = false;
  int line_no = 0;
  auto number = [&](const std::string& s, int line, const std::string& field) {
    auto d = ParseDouble(s);
    if (!d || !std::isfinite(*d)) throw InputError(source, line, field, fmt::format("'{}' is not a number", s));
    return *d;
  };
  LineCursor cursor(text);
  while (cursor.Next()) {
    line_no = cursor.number();
    std::string line(cursor.line());
    if (line.empty()) continue;
    std::smatch m;
    if (line[0] == ';') {
      if (std::regex_search(line, m, kData)) data[m[1]] = number(m[2], line_no, m[1]);
      continue;
    }
    if (end) throw InputError(source, line_no, "M17", "text after M17");
    if (!header) {
      if (line != "%_N_AX_EEC_INI")
        throw InputError(source, line_no, "header", fmt::format("expected %_N_AX_EEC_INI, found '{}'", line));
      header = true;
      continue;
    }
    if (line == "CHANDATA(1)") continue;
    if (line == "M17") {
      end = true;
      continue;
    }
    const std::string code = line.substr(0, line.find(';'));
    if (std::regex_search(code, m, kParam)) {
      if (axis && *axis != m[3]) throw InputError(source, line_no, "axis", "the file mixes axes " + *axis + " and " + m[3].str());
      axis = m[3];
      params[m[1]] = number(m[4], line_no, "$AA_ENC_COMP_" + m[1].str());
    } else if (std::regex_search(code, m, kComp)) {
      if (axis && *axis != m[3]) throw InputError(source, line_no, "axis", "the file mixes axes " + *axis + " and " + m[3].str());
      axis = m[3];
      const auto idx_opt = ParseInt(m[2].str());
      if (!idx_opt || *idx_opt > 10000000) throw InputError(source, line_no, "$AA_ENC_COMP", "point index out of range");
      const long long idx = *idx_opt;
      if (values.count(idx)) throw InputError(source, line_no, "$AA_ENC_COMP", fmt::format("point {} given twice", idx));
      values[idx] = number(m[4], line_no, "$AA_ENC_COMP");
      value_line[idx] = line_no;
    } else {
      throw InputError(source, line_no, "line", fmt::format("not a LEC assignment: '{}'", line));
    }
  }
  if (!header) throw InputError(source, 0, "header", "no %_N_AX_EEC_INI line");
  if (!end) throw InputError(source, 0, "M17", "the file does not end with M17");
  for (const char* k : {"STEP", "MIN", "MAX"})
    if (!params.count(k)) throw InputError(source, 0, std::string("$AA_ENC_COMP_") + k, "missing");
  if (params.count("IS_MODULO") && params["IS_MODULO"] != 0)
    throw InputError(source, 0, "$AA_ENC_COMP_IS_MODULO", "modulo (rotary) tables are not supported");
  const double step = params["STEP"], lo = params["MIN"], hi = params["MAX"];
  if (!(step > 0)) throw InputError(source, 0, "$AA_ENC_COMP_STEP", "must be > 0");
  if (!(hi > lo)) throw InputError(source, 0, "$AA_ENC_COMP_MAX", "must be greater than $AA_ENC_COMP_MIN");
  const double n_real = (hi - lo) / step + 1;
  const long long n = std::llround(n_real);
  if (std::abs(n_real - static_cast<double>(n)) > 1e-6)
    throw InputError(source, 0, "$AA_ENC_COMP_STEP", "(MAX − MIN) is not a whole number of steps");
  // An index outside 0…n−1 is named at its line first (with the right count it is the only fault:
  // "give 1201 points but the file holds 1201 values" said nothing).
  for (const auto& [idx, line] : value_line)
    if (idx >= n)
      throw InputError(source, line, "$AA_ENC_COMP",
                       fmt::format("point index {} is outside 0…{} (MIN/MAX/STEP give {} points)", idx, n - 1, n));
  if (static_cast<long long>(values.size()) != n)
    throw InputError(source, 0, "$AA_ENC_COMP",
                     fmt::format("MIN/MAX/STEP give {} points but the file holds {} values (indices 0…{})", n,
                                 values.size(), n - 1));
  CompensationTable t;
  t.axis = axis.value_or("");
  t.bidirectional = false;
  const double abs_um = data.count("SA_TEMP_COMP_ABS_VALUE") ? data["SA_TEMP_COMP_ABS_VALUE"] * 1000.0 : 0.0;
  std::vector<int> point_lines;
  for (long long i = 0; i < n; ++i) {
    point_lines.push_back(value_line[i]);
    t.position_mm.push_back(lo + step * static_cast<double>(i));
    const double c = -values[i] * 1000.0 - abs_um;
    t.forward_um.push_back(c);
    t.reverse_um.push_back(c);
  }
  t.backlash_um = data.count("MA_BACKLASH") ? data["MA_BACKLASH"] * 1000.0 : 0.0;
  if (data.count("SA_TEMP_COMP_SLOPE")) t.thermal_tan_beta_um_per_mm = -data["SA_TEMP_COMP_SLOPE"] * 1000.0;
  if (data.count("SA_TEMP_COMP_REF_POSITION")) t.thermal_reference_mm = data["SA_TEMP_COMP_REF_POSITION"];
  ValidateReadTable(t, source, point_lines);
  return t;
}

double SinumerikValueAtReferenceUm(const CompensationTable& t) {
  const double ref = t.reference_position_mm;
  if (std::isnan(ref) || t.position_mm.empty() || ref < t.position_mm.front() || ref > t.position_mm.back())
    return std::nan("");
  const double at_ref = AppliedCorrectionUm(t, ref, Direction::kForward) +
                        t.thermal_tan_beta_um_per_mm * (t.thermal_reference_mm - ref) - 0.5 * t.backlash_um;
  return -at_ref;
}

}  // namespace trueaxis::exporter
