#include "trueaxis/measure/column_map.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/toml_reader.hpp"

namespace trueaxis::measure {
namespace {

constexpr const char* kKeys =
    "target_mm, target_in, deviation_um, deviation_mm, deviation_nm, run, direction, "
    "deviation_um[<run><+|->], time_s, t_<sensor>_c, forward, reverse";

struct UnitOfKey {
  const char* suffix;
  const char* unit;
  double scale;
};

// The deviation keys: the unit named by the key, and its factor to µm.
constexpr UnitOfKey kDeviationUnits[] = {{"um", "um", 1.0}, {"mm", "mm", 1000.0}, {"nm", "nm", 0.001}};

std::optional<UnitOfKey> DeviationUnit(std::string_view suffix) {
  for (const auto& u : kDeviationUnits)
    if (suffix == u.suffix) return u;
  return std::nullopt;
}

void SetOnce(ColumnMap& map, std::optional<MappedColumn>& slot, MappedColumn col, int line) {
  if (slot)
    throw InputError(map.source, line, col.key,
                     fmt::format("given twice (already '{}={}')", slot->key, slot->column));
  slot = std::move(col);
}

// deviation_<unit>[<run><+|->] → (run, direction, unit); nullopt when `key` has no such form.
std::optional<RunColumn> WideKey(const ColumnMap& map, const std::string& key, int line) {
  if (key.rfind("deviation_", 0) != 0) return std::nullopt;
  const auto open = key.find('[');
  if (open == std::string::npos) return std::nullopt;
  const auto unit = DeviationUnit(std::string_view(key).substr(10, open - 10));
  const std::string inside = key.back() == ']' ? key.substr(open + 1, key.size() - open - 2) : "";
  const char sign = inside.empty() ? '?' : inside.back();
  const auto run = ParseInt(std::string_view(inside).substr(0, inside.empty() ? 0 : inside.size() - 1));
  if (!unit || (sign != '+' && sign != '-') || !run || *run < 1 || *run > 100000)
    throw InputError(map.source, line, key,
                     "expected deviation_um[<run><+|->] (or _mm, _nm), e.g. deviation_um[1+] for run 1 forward");
  RunColumn rc;
  rc.run = static_cast<int>(*run);
  rc.direction = sign == '+' ? Direction::kForward : Direction::kReverse;
  rc.deviation = MappedColumn{key, "", unit->unit, unit->scale};
  return rc;
}

}  // namespace

int ColumnMap::LineOf(const std::string& key) const {
  auto it = key_lines.find(key);
  return it == key_lines.end() ? 0 : it->second;
}

std::vector<const MappedColumn*> ColumnMap::Columns() const {
  std::vector<const MappedColumn*> out;
  for (const auto* c : {&target, &deviation, &run, &direction, &time})
    if (*c) out.push_back(&**c);
  for (const auto& [sensor, c] : temperatures) out.push_back(&c);
  for (const auto& rc : run_columns) out.push_back(&rc.deviation);
  return out;
}

void SetColumnMapKey(ColumnMap& map, const std::string& key_in, const std::string& value_in, int line) {
  const std::string key(Trim(key_in));
  const std::string value(Trim(value_in));
  if (key.empty()) throw InputError(map.source, line, "(empty key)", fmt::format("expected key=column; keys: {}", kKeys));
  if (value.empty()) throw InputError(map.source, line, key, "no column name given (key=column)");
  if (line > 0) map.key_lines[key] = line;
  if (key == "forward" || key == "reverse") {
    const Direction d = key == "forward" ? Direction::kForward : Direction::kReverse;
    std::size_t start = 0;
    while (start <= value.size()) {
      const auto bar = value.find('|', start);
      const std::string word = LowerAscii(Trim(std::string_view(value).substr(start, bar == std::string::npos ? std::string::npos : bar - start)));
      if (word.empty()) throw InputError(map.source, line, key, fmt::format("empty direction word in '{}'", value));
      for (const auto& [w, other] : map.direction_words)
        if (w == word && other != d)
          throw InputError(map.source, line, key, fmt::format("'{}' is already a word for the other direction", word));
      map.direction_words.emplace_back(word, d);
      if (bar == std::string::npos) break;
      start = bar + 1;
    }
    return;
  }
  if (auto rc = WideKey(map, key, line)) {
    for (const auto& other : map.run_columns)
      if (other.run == rc->run && other.direction == rc->direction)
        throw InputError(map.source, line, key,
                         fmt::format("run {} {} is already mapped to '{}'", rc->run, DirectionSymbol(rc->direction),
                                     other.deviation.column));
    rc->deviation.column = value;
    map.run_columns.push_back(std::move(*rc));
    return;
  }
  if (key == "target_mm") return SetOnce(map, map.target, {key, value, "mm", 1.0}, line);
  if (key == "target_in") return SetOnce(map, map.target, {key, value, "in", 25.4}, line);
  if (key.rfind("deviation_", 0) == 0)
    if (auto u = DeviationUnit(std::string_view(key).substr(10)))
      return SetOnce(map, map.deviation, {key, value, u->unit, u->scale}, line);
  if (key == "run") return SetOnce(map, map.run, {key, value, "", 1.0}, line);
  if (key == "direction") return SetOnce(map, map.direction, {key, value, "", 1.0}, line);
  if (key == "time_s") return SetOnce(map, map.time, {key, value, "s", 1.0}, line);
  if (key.size() > 4 && key.rfind("t_", 0) == 0 && key.substr(key.size() - 2) == "_c") {
    const std::string sensor = key.substr(2, key.size() - 4);
    for (const auto& [s, c] : map.temperatures)
      if (s == sensor) throw InputError(map.source, line, key, fmt::format("given twice (already '{}')", c.column));
    map.temperatures.emplace_back(sensor, MappedColumn{key, value, "c", 1.0});
    return;
  }
  throw InputError(map.source, line, key, fmt::format("unknown mapping key; expected {}", kKeys));
}

ColumnMap ParseColumnsOption(std::string_view text, const std::string& source) {
  ColumnMap map;
  map.source = source;
  if (Trim(text).empty()) throw InputError(source, 0, "", fmt::format("empty mapping; expected key=column pairs: {}", kKeys));
  for (auto pair : SplitCsvFields(text)) {
    const auto eq = pair.find('=');
    if (eq == std::string_view::npos)
      throw InputError(source, 0, std::string(pair), "expected key=column (e.g. target_mm=Target [mm])");
    SetColumnMapKey(map, std::string(pair.substr(0, eq)), std::string(pair.substr(eq + 1)));
  }
  return map;
}

ColumnMap ParseColumnMapToml(std::string_view text, const std::string& source) {
  ColumnMap map;
  map.source = source;
  const toml::table doc = ParseTomlOrThrow(text, source);
  for (const auto& [k, node] : doc) {
    const std::string key(k.str());
    const int line = static_cast<int>(node.source().begin.line);
    if (key == "metadata") {
      const auto* t = node.as_table();
      if (!t) throw InputError(source, line, key, "expected a table of key = \"value\"");
      for (const auto& [mk, mv] : *t) {
        const auto* s = mv.as_string();
        if (!s) throw InputError(source, static_cast<int>(mv.source().begin.line), "metadata." + std::string(mk.str()), "expected a string");
        map.metadata.emplace_back(std::string(mk.str()), s->get());
      }
      continue;
    }
    if (const auto* s = node.as_string()) {
      SetColumnMapKey(map, key, s->get(), line);
    } else if (const auto* a = node.as_array(); a && (key == "forward" || key == "reverse")) {
      for (const auto& w : *a) {
        const auto* ws = w.as_string();
        if (!ws) throw InputError(source, line, key, "expected direction words as strings");
        SetColumnMapKey(map, key, ws->get(), line);
      }
    } else {
      throw InputError(source, line, key, "expected a column name in quotes (forward/reverse: a word or a list of words)");
    }
  }
  if (map.Columns().empty()) throw InputError(source, 0, "", fmt::format("maps no column; keys: {}", kKeys));
  return map;
}

ColumnMap ReadColumnMapFile(const std::string& path) { return ParseColumnMapToml(ReadTextFile(path), path); }

std::optional<std::string> UnitTagOf(std::string_view column) {
  column = Trim(column);
  if (column.empty()) return std::nullopt;
  const char close = column.back();
  const char open = close == ']' ? '[' : close == ')' ? '(' : '\0';
  if (!open) return std::nullopt;
  const auto at = column.rfind(open);
  if (at == std::string_view::npos) return std::nullopt;
  std::string tag = LowerAscii(Trim(column.substr(at + 1, column.size() - at - 2)));
  // "µm" (micro sign U+00B5) and "μm" (Greek mu U+03BC) as UTF-8, "°C" with the degree sign.
  if (tag == "um" || tag == "\xC2\xB5m" || tag == "\xCE\xBCm" || tag == "micron" || tag == "microns") return "um";
  if (tag == "mm" || tag == "nm" || tag == "m") return tag;
  if (tag == "in" || tag == "inch" || tag == "inches" || tag == "\"") return "in";
  if (tag == "s" || tag == "sec") return "s";
  if (tag == "min" || tag == "h") return tag;
  if (tag == "c" || tag == "degc" || tag == "\xC2\xB0" "c") return "c";
  if (tag == "f" || tag == "degf" || tag == "\xC2\xB0" "f") return "f";
  if (tag == "k") return "k";
  return std::nullopt;
}

std::optional<Direction> MappedDirection(const ColumnMap& map, std::string_view word) {
  const std::string w = LowerAscii(Trim(word));
  for (const auto& [mw, d] : map.direction_words)
    if (mw == w) return d;
  if (auto d = ParseDirection(w)) return d;
  if (w == "rev" || w == "-1") return Direction::kReverse;
  if (w == "1" || w == "+1") return Direction::kForward;
  return std::nullopt;
}

}  // namespace trueaxis::measure
