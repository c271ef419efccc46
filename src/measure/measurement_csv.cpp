#include "trueaxis/measure/measurement_csv.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "point_fields.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::measure {
namespace {

enum class Column { kRun, kDirection, kTarget, kDeviation, kTime, kTemperature };

struct ColumnSpec {
  Column kind;
  std::string name;
  std::size_t sensor = 0;
};

}  // namespace

Measurement ParseMeasurementCsv(std::string_view text, const std::string& source) {
  Measurement m;
  m.source = source;
  std::vector<ColumnSpec> columns;
  bool have_header = false;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  int line_no = 0;
  while (cursor.Next()) {
    line_no = cursor.number();
    const std::string_view line = cursor.line();
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (auto kv = ParseMetadataComment(line); kv && !have_header) m.SetMeta(std::string(kv->first), std::string(kv->second), line_no);
      continue;  // other comments are free text
    }
    auto fields = SplitCsvFields(line);
    if (!have_header) {
      have_header = true;
      bool seen[4] = {false, false, false, false};
      for (auto f : fields) {
        std::string name(f);
        ColumnSpec spec{Column::kRun, name};
        if (name == "run") spec.kind = Column::kRun;
        else if (name == "direction") spec.kind = Column::kDirection;
        else if (name == "target_mm") spec.kind = Column::kTarget;
        else if (name == "deviation_um") spec.kind = Column::kDeviation;
        else if (name == "time_s") {
          if (m.has_time) throw InputError(source, line_no, name, "column given twice");
          spec.kind = Column::kTime;
          m.has_time = true;
        } else if (name.size() > 4 && name.rfind("t_", 0) == 0 && name.substr(name.size() - 2) == "_c") {
          spec.kind = Column::kTemperature;
          std::string sensor = name.substr(2, name.size() - 4);
          if (m.SensorIndex(sensor)) throw InputError(source, line_no, name, "column given twice");
          spec.sensor = m.sensor_names.size();
          m.sensor_names.push_back(sensor);
        } else {
          throw InputError(source, line_no, name.empty() ? "(empty)" : name,
                           "unknown column; expected run, direction, target_mm, deviation_um, time_s or t_<sensor>_c "
                           "(a laser software's own export: map its columns with --columns or --column-map, "
                           "docs/formats.md)");
        }
        if (spec.kind <= Column::kDeviation) {
          int k = static_cast<int>(spec.kind);
          if (seen[k]) throw InputError(source, line_no, name, "column given twice");
          seen[k] = true;
        }
        columns.push_back(spec);
      }
      const char* required[4] = {"run", "direction", "target_mm", "deviation_um"};
      for (int k = 0; k < 4; ++k)
        if (!seen[k]) throw InputError(source, line_no, required[k], "required column is missing from the header");
      continue;
    }
    if (fields.size() != columns.size())
      throw InputError(source, line_no, "",
                       fmt::format("{} fields, but the header has {} columns", fields.size(), columns.size()));
    MeasurementPoint p;
    p.source_line = line_no;
    p.temperatures_c.assign(m.sensor_names.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const auto& col = columns[c];
      std::string_view f = fields[c];
      switch (col.kind) {
        case Column::kRun:
          p.run = detail::ReadRunField(f, source, line_no, col.name);
          break;
        case Column::kDirection: {
          auto d = ParseDirection(f);
          if (!d) throw InputError(source, line_no, col.name, fmt::format("'{}' is not a direction; use + or -", f));
          p.direction = *d;
          break;
        }
        case Column::kTarget:
          p.target_mm = detail::ReadQuantityField(f, detail::Quantity::kTargetMm, source, line_no, col.name);
          break;
        case Column::kDeviation:
          p.deviation_um = detail::ReadQuantityField(f, detail::Quantity::kDeviationUm, source, line_no, col.name);
          break;
        case Column::kTime:
          p.time_s = detail::ReadQuantityField(f, detail::Quantity::kTimeS, source, line_no, col.name);
          break;
        case Column::kTemperature:
          if (auto t = detail::ReadTemperatureField(f, source, line_no, col.name)) p.temperatures_c[col.sensor] = *t;
          break;
      }
    }
    m.points.push_back(std::move(p));
  }
  if (!have_header) throw InputError(source, line_no, "", "no header line: the file is empty or holds only comments");
  return m;
}

Measurement ReadMeasurementCsv(const std::string& path) { return ParseMeasurementCsv(ReadTextFile(path), path); }

std::string FormatMeasurementCsv(const Measurement& m) {
  std::string out;
  for (const auto& [k, v] : m.metadata) out += fmt::format("# {}: {}\n", k, v);
  out += "run,direction,target_mm,deviation_um";
  if (m.has_time) out += ",time_s";
  for (const auto& s : m.sensor_names) out += ",t_" + s + "_c";
  out += '\n';
  for (const auto& p : m.points) {
    out += fmt::format("{},{},{},{}", p.run, DirectionSymbol(p.direction), FormatShortest(p.target_mm),
                       FormatShortest(p.deviation_um));
    if (m.has_time) out += "," + (p.time_s ? FormatShortest(*p.time_s) : std::string("0"));
    for (std::size_t i = 0; i < m.sensor_names.size(); ++i) {
      out += ',';
      if (i < p.temperatures_c.size() && !std::isnan(p.temperatures_c[i])) out += FormatShortest(p.temperatures_c[i]);
    }
    out += '\n';
  }
  return out;
}

void WriteMeasurementCsv(const Measurement& m, const std::string& path) {
  WriteTextFile(path, FormatMeasurementCsv(m));
}

}  // namespace trueaxis::measure
