#include "trueaxis/measure/ecmc_dat.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <tuple>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::measure {
namespace {

constexpr long long kMaxIndex = 100000;

struct Value {
  double value = 0;
  int line = 0;
  std::string key;  // as written, for error messages
};

struct ScalarInt {
  long long value = 0;
  int line = 0;
};

std::string Lower(std::string_view s) {
  std::string out;
  for (char c : s) out += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool IsIdentifier(std::string_view s) {
  if (s.empty()) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

// Micrometres per unit named by UNIT=.
std::optional<double> UmPerUnit(std::string_view unit) {
  const auto u = Lower(unit);
  if (u == "mm") return 1000.0;
  if (u == "um" || u == "µm" || u == "micron" || u == "microns") return 1.0;
  if (u == "nm") return 0.001;
  if (u == "m") return 1e6;
  if (u == "in" || u == "inch") return 25400.0;
  return std::nullopt;
}

}  // namespace

Measurement ParseEcmcDat(std::string_view text, const std::string& source) {
  Measurement m;
  m.source = source;
  std::map<long long, Value> targets;                                   // i -> target
  std::map<std::tuple<int, long long, long long>, Value> refs;          // (dir, i, j) -> reading
  std::optional<std::pair<std::string, int>> unit;                      // value, line
  std::optional<ScalarInt> cycles, positions;
  std::map<std::string, int> scalar_lines;                              // key -> line, for duplicates
  LineCursor cursor(text);
  int line_no = 0;
  while (cursor.Next()) {
    line_no = cursor.number();
    std::string_view line = cursor.line();
    if (line.empty() || line.front() == '#') continue;
    const auto eq = line.find('=');
    if (eq == std::string_view::npos) {
      std::string shown(line.substr(0, std::min<std::size_t>(line.size(), 40)));
      throw InputError(source, line_no, shown, "expected KEY=VALUE or a '#' comment");
    }
    const std::string key(Trim(line.substr(0, eq)));
    const std::string_view value = Trim(line.substr(eq + 1));
    if (key == "TEST_DATA") {
      // Real files glue the first comment to this key: "TEST_DATA=# Input data file ...".
      auto desc = value;
      while (!desc.empty() && desc.front() == '#') desc.remove_prefix(1);
      if (!Trim(desc).empty()) m.SetMeta("description", std::string(Trim(desc)), line_no);
      continue;
    }
    const auto bracket = key.find('[');
    if (bracket != std::string::npos) {
      const std::string name = key.substr(0, bracket);
      if (key.back() != ']')
        throw InputError(source, line_no, key, "unterminated index: expected NAME[i] or NAME[i,j]");
      const std::string inside = key.substr(bracket + 1, key.size() - bracket - 2);
      std::vector<long long> idx;
      std::size_t start = 0;
      while (true) {
        auto comma = inside.find(',', start);
        auto part = std::string_view(inside).substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        auto v = ParseInt(part);
        if (!v || *v < 1 || *v > kMaxIndex)
          throw InputError(source, line_no, key,
                           fmt::format("index '{}' is not a whole number in 1..{}", Trim(part), kMaxIndex));
        idx.push_back(*v);
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      int dir = -1;
      if (name == "TGT_DATA") {
        if (idx.size() != 1) throw InputError(source, line_no, key, "TGT_DATA takes one index: TGT_DATA[<position>]");
      } else if (name == "REF_DATA_FWD" || name == "REF_DATA_BWD") {
        if (idx.size() != 2)
          throw InputError(source, line_no, key, fmt::format("{} takes two indices: {}[<position>,<cycle>]", name, name));
        dir = name == "REF_DATA_FWD" ? 0 : 1;
      } else {
        throw InputError(source, line_no, key,
                         "unknown indexed variable; expected TGT_DATA[i], REF_DATA_FWD[i,j] or REF_DATA_BWD[i,j]");
      }
      auto v = ParseDouble(value);
      if (!v || !std::isfinite(*v))
        throw InputError(source, line_no, key, fmt::format("'{}' is not a finite number", value));
      Value val{*v, line_no, key};
      if (dir < 0) {
        auto [it, fresh] = targets.emplace(idx[0], val);
        if (!fresh) throw InputError(source, line_no, key, fmt::format("given twice (first on line {})", it->second.line));
      } else {
        auto [it, fresh] = refs.emplace(std::make_tuple(dir, idx[0], idx[1]), val);
        if (!fresh) throw InputError(source, line_no, key, fmt::format("given twice (first on line {})", it->second.line));
      }
      continue;
    }
    if (!IsIdentifier(key)) throw InputError(source, line_no, key.empty() ? "(empty key)" : key, "not a valid variable name");
    if (auto [it, fresh] = scalar_lines.emplace(key, line_no); !fresh)
      throw InputError(source, line_no, key, fmt::format("given twice (first on line {})", it->second));
    if (key == "UNIT") {
      if (!UmPerUnit(value))
        throw InputError(source, line_no, key, fmt::format("unknown unit '{}'; expected mm, um, nm, m or in", value));
      unit = std::make_pair(std::string(value), line_no);
    } else if (key == "CYCLES" || key == "POSITIONS" || key == "DEC") {
      auto v = ParseInt(value);
      if (!v || *v < 1 || *v > kMaxIndex)
        throw InputError(source, line_no, key, fmt::format("'{}' is not a whole number in 1..{}", value, kMaxIndex));
      if (key == "CYCLES") cycles = ScalarInt{*v, line_no};
      if (key == "POSITIONS") positions = ScalarInt{*v, line_no};
    }
    m.SetMeta(Lower(key), std::string(value), line_no);
  }

  if (targets.empty() && refs.empty())
    throw InputError(source, line_no, "TGT_DATA",
                     "no TGT_DATA[i] or REF_DATA_FWD/BWD[i,j] entries: empty file or not an ecmc ISO 230-2 file");
  if (targets.empty())
    throw InputError(source, refs.begin()->second.line, "TGT_DATA", "REF_DATA given but no TGT_DATA[i] target at all");

  const double scale = unit ? *UmPerUnit(unit->first) : 1000.0;  // the format's default unit is mm
  if (!unit) m.SetMeta("unit", "mm");
  m.SetMeta("format", "ecmc dat");

  if (positions && static_cast<long long>(targets.size()) != positions->value)
    throw InputError(source, positions->line, "POSITIONS",
                     fmt::format("declares {} positions but the file defines {} TGT_DATA[i]", positions->value,
                                 targets.size()));
  long long max_cycle = 0;
  std::map<long long, bool> target_has_data;
  for (const auto& [k, v] : refs) {
    const auto [dir, i, j] = k;
    if (!targets.count(i))
      throw InputError(source, v.line, v.key, fmt::format("position {} has no TGT_DATA[{}]", i, i));
    if (cycles && j > cycles->value)
      throw InputError(source, v.line, v.key,
                       fmt::format("cycle {} is beyond CYCLES={} (line {})", j, cycles->value, cycles->line));
    max_cycle = std::max(max_cycle, j);
    target_has_data[i] = true;
  }
  for (const auto& [i, t] : targets)
    if (!target_has_data.count(i))
      throw InputError(source, t.line, t.key, fmt::format("position {} has no REF_DATA_FWD/BWD readings", i));
  if (cycles && max_cycle < cycles->value)
    throw InputError(source, cycles->line, "CYCLES",
                     fmt::format("declares {} cycles but the data has readings for {} only", cycles->value, max_cycle));

  for (const auto& [k, v] : refs) {
    const auto [dir, i, j] = k;
    MeasurementPoint p;
    p.run = static_cast<int>(j);
    p.direction = dir == 0 ? Direction::kForward : Direction::kReverse;
    // mm files keep their target text's exact double (no ×1000/1000 round trip).
    p.target_mm = scale == 1000.0 ? targets.at(i).value : targets.at(i).value * scale / 1000.0;
    // Difference first, then scale: keeps the sub-nm digits of readings like -10.0000990190.
    p.deviation_um = (v.value - targets.at(i).value) * scale;
    if (auto why = ImplausiblePositionMm(p.target_mm)) throw InputError(source, targets.at(i).line, targets.at(i).key, *why);
    if (auto why = ImplausibleDeviationUm(p.deviation_um))
      throw InputError(source, v.line, v.key, "reading minus target: " + *why);
    p.source_line = v.line;
    m.points.push_back(std::move(p));
  }
  std::stable_sort(m.points.begin(), m.points.end(),
                   [](const auto& a, const auto& b) { return a.source_line < b.source_line; });
  return m;
}

Measurement ReadEcmcDat(const std::string& path) { return ParseEcmcDat(ReadTextFile(path), path); }

}  // namespace trueaxis::measure
