#include "trueaxis/measure/mapped_csv.hpp"

#include <algorithm>
#include <limits>

#include <fmt/format.h>

#include "point_fields.hpp"
#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"

namespace trueaxis::measure {
namespace {

constexpr const char* kRunHelp =
    "a positioning test needs each reading's run (cycle) and direction: map run=<column> and "
    "direction=<column>, or, for a file with one column per run and direction, deviation_um[1+]=<column>, "
    "deviation_um[1-]=<column>, …";

const char* UnitName(const std::string& unit) {
  if (unit == "um") return "µm";
  if (unit == "c") return "°C";
  if (unit == "in") return "inch";
  return unit.c_str();
}

// The mapping must make a positioning test: one layout, every part of it.
void CheckLayout(const ColumnMap& map) {
  if (!map.target)
    throw InputError(map.source, 0, "target_mm", "the mapping names no target column (target_mm=<column>, or target_in=<column> for inches)");
  if (!map.run_columns.empty()) {
    for (const auto* slot : {&map.run, &map.direction, &map.deviation})
      if (*slot)
        throw InputError(map.source, map.LineOf((*slot)->key), (*slot)->key,
                         "the mapping gives one deviation column per run (deviation_um[<run><+|->]) and also a "
                         "long-layout column: use one layout");
    return;
  }
  if (!map.deviation)
    throw InputError(map.source, 0, "deviation_um",
                     "the mapping names no deviation column (deviation_um=, deviation_mm= or deviation_nm=<column>)");
  if (!map.run) throw InputError(map.source, 0, "run", fmt::format("the mapping names no run column: {}", kRunHelp));
  if (!map.direction)
    throw InputError(map.source, 0, "direction", fmt::format("the mapping names no direction column: {}", kRunHelp));
}

// Index of each mapped column in `header` (case-insensitive, trimmed); npos when absent.
std::vector<std::size_t> Locate(const std::vector<const MappedColumn*>& cols, const std::vector<std::string_view>& header) {
  std::vector<std::size_t> at(cols.size(), std::string::npos);
  for (std::size_t k = 0; k < cols.size(); ++k) {
    const std::string want = LowerAscii(Trim(cols[k]->column));
    for (std::size_t i = 0; i < header.size(); ++i)
      if (LowerAscii(Trim(header[i])) == want) {
        at[k] = i;
        break;
      }
  }
  return at;
}

}  // namespace

Measurement ParseMappedCsv(std::string_view text, const std::string& source, const ColumnMap& map) {
  CheckLayout(map);
  Measurement m;
  m.source = source;
  const auto cols = map.Columns();
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV

  // The header: the first line holding every mapped column. Remember the line closest to one, to
  // name what it lacks when none does.
  std::vector<std::size_t> at;
  std::size_t header_size = 0;
  int header_line = 0, best_line = 0;
  std::size_t best_found = 0;
  std::vector<std::string_view> best_fields;
  LineCursor cursor(canonical);
  while (cursor.Next()) {
    const std::string_view line = cursor.line();
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (auto kv = ParseMetadataComment(line)) m.SetMeta(std::string(kv->first), std::string(kv->second), cursor.number());
      continue;
    }
    const auto fields = SplitCsvFields(line);
    const auto found = Locate(cols, fields);
    const auto n = static_cast<std::size_t>(std::count_if(found.begin(), found.end(), [](auto i) { return i != std::string::npos; }));
    if (n == cols.size()) {
      header_line = cursor.number();
      header_size = fields.size();
      at = found;
      for (std::size_t k = 0; k < cols.size(); ++k)
        if (std::count_if(fields.begin(), fields.end(),
                          [&](auto f) { return LowerAscii(Trim(f)) == LowerAscii(Trim(cols[k]->column)); }) > 1)
          throw InputError(source, header_line, cols[k]->column,
                           fmt::format("the header names this column more than once: '{}' cannot tell which one",
                                       cols[k]->key));
      break;
    }
    if (best_line == 0 || n > best_found) {
      best_line = cursor.number();
      best_found = n;
      best_fields = fields;
    }
  }
  if (header_line == 0) {
    if (best_line == 0) throw InputError(source, cursor.number(), "", "no header line: the file is empty or holds only comments");
    const auto found = Locate(cols, best_fields);
    std::string has;
    for (auto f : best_fields) has += (has.empty() ? "'" : ", '") + std::string(f) + "'";
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (found[k] == std::string::npos)
        throw InputError(source, best_line, cols[k]->column,
                         fmt::format("mapped column (for {} in {}{}) is not in the header; the closest line has {}",
                                     cols[k]->key, map.source,
                                     map.LineOf(cols[k]->key) ? fmt::format(" line {}", map.LineOf(cols[k]->key)) : "",
                                     has));
  }
  // A unit stated in a column's name must be the unit its key reads: never a silent ×1000.
  for (const auto* c : cols) {
    if (c->unit.empty()) continue;
    const auto tag = UnitTagOf(c->column);
    if (!tag || *tag == c->unit) continue;
    const bool deviation = c->key.rfind("deviation_", 0) == 0, target = c->key.rfind("target_", 0) == 0;
    std::string fix = fmt::format("convert the column to {} first", UnitName(c->unit));
    if (deviation && (*tag == "um" || *tag == "mm" || *tag == "nm"))
      fix = fmt::format("map it as deviation_{}{} to have it converted", *tag, c->key.substr(c->key.find('[') == std::string::npos ? c->key.size() : c->key.find('[')));
    if (target && (*tag == "mm" || *tag == "in")) fix = fmt::format("map it as target_{} to have it converted", *tag);
    throw InputError(source, header_line, c->column,
                     fmt::format("the column's name says {}, but the mapping reads it as {} ({}): {}", UnitName(*tag),
                                 c->key, UnitName(c->unit), fix));
  }
  for (const auto& kv : map.metadata) {
    if (auto own = m.Meta(kv.first); own && *own != kv.second)
      throw InputError(source, m.MetaLine(kv.first), kv.first,
                       fmt::format("the file says '{}' but {} [metadata] says '{}'", *own, map.source, kv.second));
    m.SetMeta(kv.first, kv.second);
  }
  m.SetMeta("format", "mapped csv");
  for (const auto& [sensor, c] : map.temperatures) m.sensor_names.push_back(sensor);
  m.has_time = map.time.has_value();

  const auto index_of = [&](const MappedColumn& c) {
    for (std::size_t k = 0; k < cols.size(); ++k)
      if (cols[k] == &c) return at[k];
    return std::string::npos;
  };
  while (cursor.Next()) {
    const int line_no = cursor.number();
    const std::string_view line = cursor.line();
    if (line.empty() || line.front() == '#') continue;
    const auto fields = SplitCsvFields(line);
    if (fields.size() != header_size)
      throw InputError(source, line_no, "",
                       fmt::format("{} fields, but the header (line {}) has {} columns", fields.size(), header_line,
                                   header_size));
    if (std::all_of(at.begin(), at.end(), [&](auto i) { return fields[i].empty(); })) continue;  // a blank sheet row
    const auto field = [&](const MappedColumn& c) { return fields[index_of(c)]; };
    MeasurementPoint p;
    p.source_line = line_no;
    p.temperatures_c.assign(m.sensor_names.size(), std::numeric_limits<double>::quiet_NaN());
    p.target_mm = detail::ReadQuantityField(field(*map.target), detail::Quantity::kTargetMm, source, line_no,
                                            map.target->column, map.target->scale);
    if (map.time) p.time_s = detail::ReadQuantityField(field(*map.time), detail::Quantity::kTimeS, source, line_no, map.time->column);
    for (std::size_t s = 0; s < map.temperatures.size(); ++s) {
      const auto& c = map.temperatures[s].second;
      if (auto t = detail::ReadTemperatureField(field(c), source, line_no, c.column)) p.temperatures_c[s] = *t;
    }
    if (map.run_columns.empty()) {
      p.run = detail::ReadRunField(field(*map.run), source, line_no, map.run->column);
      const auto word = field(*map.direction);
      const auto d = MappedDirection(map, word);
      if (!d)
        throw InputError(source, line_no, map.direction->column,
                         fmt::format("'{}' is not a direction word trueaxis knows (+/-, up/down, fwd/rev, forward/"
                                     "backward, pos/neg, 1/-1): name the file's words in the mapping, forward={}|… or "
                                     "reverse={}|…", word, word, word));
      p.direction = *d;
      p.deviation_um = detail::ReadQuantityField(field(*map.deviation), detail::Quantity::kDeviationUm, source, line_no,
                                                 map.deviation->column, map.deviation->scale);
      m.points.push_back(std::move(p));
      continue;
    }
    for (const auto& rc : map.run_columns) {  // wide layout: one point per filled run column
      const auto f = field(rc.deviation);
      if (f.empty()) continue;  // that run has no reading at this target
      MeasurementPoint q = p;
      q.run = rc.run;
      q.direction = rc.direction;
      q.deviation_um = detail::ReadQuantityField(f, detail::Quantity::kDeviationUm, source, line_no, rc.deviation.column,
                                                 rc.deviation.scale);
      m.points.push_back(std::move(q));
    }
  }
  return m;
}

}  // namespace trueaxis::measure
