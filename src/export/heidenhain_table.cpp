#include "trueaxis/export/heidenhain_table.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::exporter {

namespace {

std::string Mm4(double mm) { return fmt::format("{:+.4f}", std::round(mm * 1e4) / 1e4 + 0.0); }

std::string Upper(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

struct Lines {
  std::vector<std::pair<int, std::string>> rows;  // (line number, text) of non-blank lines
};

Lines SplitLines(std::string_view text) {
  Lines l;
  std::size_t pos = 0;
  int n = 0;
  while (pos <= text.size()) {
    const std::size_t nl = text.find('\n', pos);
    std::string line(text.substr(pos, nl == std::string_view::npos ? std::string_view::npos : nl - pos));
    pos = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!Trim(line).empty()) l.rows.emplace_back(n, line);
  }
  return l;
}

// Column name → [start, end) from the header line.
struct Column {
  std::string name;
  std::size_t start, end;
};

std::vector<Column> HeaderColumns(const std::string& header) {
  std::vector<Column> cols;
  std::size_t i = 0;
  while (i < header.size()) {
    while (i < header.size() && header[i] == ' ') ++i;
    if (i >= header.size()) break;
    std::size_t j = i;
    while (j < header.size() && header[j] != ' ') ++j;
    cols.push_back({header.substr(i, j - i), i, std::string::npos});
    i = j;
  }
  for (std::size_t k = 0; k + 1 < cols.size(); ++k) cols[k].end = cols[k + 1].start;
  return cols;
}

std::string Field(const std::string& line, const Column& c) {
  if (c.start >= line.size()) return "";
  return std::string(Trim(line.substr(c.start, c.end == std::string::npos ? std::string::npos : c.end - c.start)));
}

// Checks BEGIN <name> ... and [END]; returns the rows between header and [END].
std::vector<std::pair<int, std::string>> Body(const Lines& l, const std::string& ext, const std::string& source,
                                              std::string* header) {
  if (l.rows.empty() || l.rows.front().second.rfind("BEGIN ", 0) != 0)
    throw InputError(source, l.rows.empty() ? 0 : l.rows.front().first, "BEGIN", "a table starts with 'BEGIN <name>'");
  if (Upper(l.rows.front().second).find(ext) == std::string::npos)
    throw InputError(source, l.rows.front().first, "BEGIN", fmt::format("the table name is not a {} table", ext));
  if (l.rows.size() < 2) throw InputError(source, 0, "header", "no column header line");
  if (Trim(l.rows.back().second) != "[END]") throw InputError(source, l.rows.back().first, "[END]", "the table does not end with [END]");
  *header = l.rows[1].second;
  return {l.rows.begin() + 2, l.rows.end() - 1};
}

}  // namespace

std::string WriteHeidenhainCom(const CompensationTable& t, const std::string& file_name, ValueSign sign,
                               const std::string& source) {
  ValidateTable(t, source);
  if (t.size() > static_cast<std::size_t>(kHeidenhainMaxPoints))
    throw InputError(source, 0, "--spacing",
                     fmt::format("{} points exceed the {} entries of a .COM table; choose a larger --spacing", t.size(),
                                 kHeidenhainMaxPoints));
  if (t.thermal_tan_beta_um_per_mm != 0)
    throw InputError(source, 0, "thermal", "a .COM table holds no temperature line; freeze the thermal part into it");
  const std::string axis = t.axis.empty() ? "X" : Upper(t.axis);
  const double k = SignFactor(sign);
  std::string out = fmt::format("BEGIN {} MM\n", Upper(file_name));
  out += fmt::format("{:<6}{:<14}{:<14}{}\n", "NR", "AXISPOS", axis, "BACKLASH");
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double x = t.position_mm[i];
    // Unidirectional: the ±backlash/2 split is folded in (MP_backLash must then be 0).
    const double f = AppliedCorrectionUm(t, x, Direction::kForward);
    const double r = AppliedCorrectionUm(t, x, Direction::kReverse);
    out += fmt::format("{:<6}{:<14}{:<14}{}\n", i, Mm4(x), Mm4(k * f / 1000.0), Mm4(k * (r - f) / 1000.0));
  }
  out += "[END]\n";
  return out;
}

CompensationTable ReadHeidenhainCom(std::string_view text, ValueSign sign, const std::string& source) {
  std::string header;
  const auto body = Body(SplitLines(text), ".COM", source, &header);
  const auto cols = HeaderColumns(header);
  if (cols.size() != 4 || cols[0].name != "NR" || cols[1].name != "AXISPOS" || cols[3].name != "BACKLASH")
    throw InputError(source, 2, "header", "expected columns NR, AXISPOS, <axis>, BACKLASH");
  CompensationTable t;
  t.axis = cols[2].name;
  const double k = SignFactor(sign);
  int expected_nr = 0;
  std::vector<int> point_lines;
  for (const auto& [line_no, line] : body) {
    auto nr = ParseInt(Field(line, cols[0]));
    if (!nr || *nr != expected_nr)
      throw InputError(source, line_no, "NR", fmt::format("expected {}, found '{}'", expected_nr, Field(line, cols[0])));
    ++expected_nr;
    double v[3];
    for (int c = 1; c <= 3; ++c) {
      const std::string f = Field(line, cols[static_cast<std::size_t>(c)]);
      auto d = ParseDouble(f);
      if (!d || !std::isfinite(*d))
        throw InputError(source, line_no, cols[static_cast<std::size_t>(c)].name, fmt::format("'{}' is not a number", f));
      v[c - 1] = *d;
    }
    if (!t.position_mm.empty() && !(v[0] > t.position_mm.back()))
      throw InputError(source, line_no, "AXISPOS",
                       fmt::format("compensation points must ascend ({} follows {})", v[0], t.position_mm.back()));
    t.position_mm.push_back(v[0]);
    point_lines.push_back(line_no);
    const double f = k * v[1] * 1000.0;
    t.forward_um.push_back(f);
    t.reverse_um.push_back(f + k * v[2] * 1000.0);
  }
  if (t.size() > static_cast<std::size_t>(kHeidenhainMaxPoints))
    throw InputError(source, 0, "NR", fmt::format("{} entries exceed {}", t.size(), kHeidenhainMaxPoints));
  ValidateReadTable(t, source, point_lines);
  return t;
}

std::string WriteHeidenhainCma(const std::string& axis, const std::string& file_name, const std::vector<CmaLine>& lines,
                               const std::string& source) {
  if (lines.empty()) throw InputError(source, 0, "states", "a .CMA needs at least one line");
  const auto active = std::count_if(lines.begin(), lines.end(), [](const CmaLine& l) { return l.active; });
  if (active != 1) throw InputError(source, 0, "ACTIVE", fmt::format("exactly one line must be active, {} are", active));
  std::size_t width = 18;
  for (const auto& l : lines) {
    if (Upper(l.com_file).size() < 5 || Upper(l.com_file).substr(Upper(l.com_file).size() - 4) != ".COM")
      throw InputError(source, 0, "com_file", fmt::format("'{}' is not a .COM file name", l.com_file));
    if (l.com_file.find(' ') != std::string::npos)
      throw InputError(source, 0, "com_file", fmt::format("'{}' contains a blank", l.com_file));
    width = std::max(width, l.com_file.size() + 2);
  }
  const std::string ax = axis.empty() ? "X" : Upper(axis);
  std::string out = fmt::format("BEGIN {}\n", Upper(file_name));
  out += fmt::format("{:<6}{:<{}}{:<8}{}\n", "NR", ax, width, "ACTIVE", "DOC");
  for (std::size_t i = 0; i < lines.size(); ++i)
    out += fmt::format("{:<6}{:<{}}{:<8}{}\n", i, Upper(lines[i].com_file), width, lines[i].active ? "*" : "",
                       lines[i].description);
  out += "[END]\n";
  return out;
}

std::vector<CmaLine> ReadHeidenhainCma(std::string_view text, const std::string& axis, const std::string& source) {
  std::string header;
  const auto body = Body(SplitLines(text), ".CMA", source, &header);
  const auto cols = HeaderColumns(header);
  const std::string ax = Upper(axis);
  const Column* c_nr = nullptr;
  const Column* c_ax = nullptr;
  const Column* c_active = nullptr;
  const Column* c_doc = nullptr;
  for (const auto& c : cols) {
    if (c.name == "NR") c_nr = &c;
    else if (c.name == ax) c_ax = &c;
    else if (c.name == "ACTIVE") c_active = &c;
    else if (c.name == "DOC") c_doc = &c;
  }
  if (!c_nr || !c_active) throw InputError(source, 2, "header", "expected columns NR and ACTIVE");
  if (!c_ax) throw InputError(source, 2, ax.empty() ? "axis" : ax, "no column for this axis");
  std::vector<CmaLine> lines;
  int active = 0;
  for (const auto& [line_no, line] : body) {
    auto nr = ParseInt(Field(line, *c_nr));
    if (!nr || *nr != static_cast<long long>(lines.size()))
      throw InputError(source, line_no, "NR", fmt::format("expected {}", lines.size()));
    CmaLine l;
    l.com_file = Field(line, *c_ax);
    const std::string a = Field(line, *c_active);
    if (a != "" && a != "*") throw InputError(source, line_no, "ACTIVE", fmt::format("'{}' is neither '*' nor blank", a));
    l.active = a == "*";
    active += l.active;
    if (c_doc) l.description = Field(line, *c_doc);
    lines.push_back(std::move(l));
  }
  if (active != 1) throw InputError(source, 0, "ACTIVE", fmt::format("exactly one line must be active, {} are", active));
  return lines;
}

}  // namespace trueaxis::exporter
