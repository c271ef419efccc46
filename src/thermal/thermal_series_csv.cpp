#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/thermal/thermal_series_csv.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/xlsx_workbook.hpp"

namespace trueaxis::thermal {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool EndsWith(const std::string& s, std::string_view suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

bool IsMissing(std::string_view f) {
  if (f.empty()) return true;
  std::string lower(f);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower == "nan" || lower == "na" || lower == "null";
}

enum class Kind { kTime, kPosition, kSpindle, kCoolant, kTemperature, kError };
struct Column {
  Kind kind;
  std::string header;
  std::size_t index = 0;  // into temperature or error names
};

}  // namespace

ThermalSeries ParseThermalSeriesCsv(std::string_view text, const std::string& source) {
  ThermalSeries s;
  s.source = source;
  std::vector<Column> columns;
  std::vector<double> temps, errs;  // row-major while reading
  bool have_header = false;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  int line_no = 0;
  while (cursor.Next()) {
    line_no = cursor.number();
    const std::string_view line = cursor.line();
    if (line.empty()) continue;
    if (line.front() == '#') {
      if (auto kv = ParseMetadataComment(line); kv && !have_header)
        s.metadata[std::string(kv->first)] = std::string(kv->second);
      continue;
    }
    auto fields = SplitCsvFields(line);
    if (!have_header) {
      have_header = true;
      std::set<std::string> seen;
      RefuseEmptyHeaderField(fields, source, line_no);
      for (auto f : fields) {
        std::string name(f);
        if (!seen.insert(name).second) throw InputError(source, line_no, name, "column given twice");
        Column col{Kind::kTime, name};
        if (name == "time_s") {
          s.has_time = true;
        } else if (name == "position_mm") {
          col.kind = Kind::kPosition;
          s.has_position = true;
        } else if (name == "spindle_rpm") {
          col.kind = Kind::kSpindle;
          s.has_spindle = true;
        } else if (name == "coolant") {
          col.kind = Kind::kCoolant;
          s.has_coolant = true;
        } else if (EndsWith(name, "_c") || EndsWith(name, "_C")) {
          std::string sensor = name.substr(0, name.size() - 2);
          if (sensor.rfind("t_", 0) == 0 && sensor.size() > 2) sensor = sensor.substr(2);
          if (s.TemperatureIndex(sensor))
            throw InputError(source, line_no, name, fmt::format("temperature '{}' given twice", sensor));
          col.kind = Kind::kTemperature;
          col.index = s.temperature_names.size();
          s.temperature_names.push_back(sensor);
        } else if (EndsWith(name, "_um")) {
          std::string channel = name.substr(0, name.size() - 3);
          if (channel.rfind("e_", 0) == 0 && channel.size() > 2) channel = channel.substr(2);
          if (s.ErrorIndex(channel))
            throw InputError(source, line_no, name, fmt::format("error channel '{}' given twice", channel));
          col.kind = Kind::kError;
          col.index = s.error_names.size();
          s.error_names.push_back(channel);
        } else {
          throw InputError(source, line_no, name,
                           "unknown column; expected time_s, position_mm, spindle_rpm, coolant, "
                           "t_<sensor>_c (or <sensor>_C) or e_<channel>_um (or <channel>_um)");
        }
        columns.push_back(col);
      }
      if (s.temperature_names.empty())
        throw InputError(source, line_no, "", "no temperature column (t_<sensor>_c or <sensor>_C)");
      continue;
    }
    if (fields.size() != columns.size())
      throw InputError(source, line_no, "",
                       fmt::format("{} fields, but the header has {} columns", fields.size(), columns.size()));
    const std::size_t row = s.source_line.size();
    s.source_line.push_back(line_no);
    temps.resize(temps.size() + s.temperature_names.size(), kNaN);
    errs.resize(errs.size() + s.error_names.size(), kNaN);
    double time = static_cast<double>(row);
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const Column& col = columns[c];
      std::string_view f = fields[c];
      auto number = [&](const char* what) {
        auto v = ParseDouble(f);
        if (!v || !std::isfinite(*v))
          throw InputError(source, line_no, col.header, fmt::format("'{}' is not {}", f, what));
        return *v;
      };
      switch (col.kind) {
        case Kind::kTime:
          time = number("a finite time in seconds");
          if (auto why = ImplausibleTimeS(time)) throw InputError(source, line_no, col.header, *why);
          if (!s.time_s.empty() && !(time > s.time_s.back()))
            throw InputError(source, line_no, col.header,
                             fmt::format("time {} s is not after the previous row's {} s; rows must be in "
                                         "strictly increasing time",
                                         f, FormatShortest(s.time_s.back())));
          break;
        case Kind::kPosition:
          s.position_mm.push_back(number("a finite position in mm"));
          if (auto why = ImplausiblePositionMm(s.position_mm.back())) throw InputError(source, line_no, col.header, *why);
          break;
        case Kind::kSpindle: {
          double v = number("a spindle speed in rpm");
          if (v < 0) throw InputError(source, line_no, col.header, "spindle speed must be >= 0 rpm");
          s.spindle_rpm.push_back(v);
          break;
        }
        case Kind::kCoolant: {
          auto state = ParseCoolantState(std::string(f));
          if (!state) {
            auto code = ParseInt(f);
            if (code) state = CoolantStateFromCode(static_cast<int>(*code));
          }
          if (!state)
            throw InputError(source, line_no, col.header,
                             fmt::format("'{}' is not a coolant state; use off, flood, mist, air or 0..3", f));
          s.coolant.push_back(*state);
          break;
        }
        case Kind::kTemperature: {
          if (IsMissing(f)) break;
          auto v = ParseDouble(f);
          if (!v || !std::isfinite(*v))
            throw InputError(source, line_no, col.header,
                             fmt::format("'{}' is not a temperature in °C (empty or nan = not read)", f));
          if (auto why = ImplausibleTemperatureC(*v)) throw InputError(source, line_no, col.header, *why);
          temps[row * s.temperature_names.size() + col.index] = *v;
          break;
        }
        case Kind::kError: {
          if (IsMissing(f)) break;
          auto v = ParseDouble(f);
          if (!v || !std::isfinite(*v))
            throw InputError(source, line_no, col.header,
                             fmt::format("'{}' is not an error in µm (empty or nan = not measured)", f));
          if (auto why = ImplausibleDeviationUm(*v)) throw InputError(source, line_no, col.header, "thermal error " + *why);
          errs[row * s.error_names.size() + col.index] = *v;
          break;
        }
      }
    }
    s.time_s.push_back(time);
  }
  if (!have_header) throw InputError(source, 0, "", "no header line: the file is empty or holds only comments");
  if (s.time_s.empty()) throw InputError(source, 0, "", "no data rows after the header");
  const auto n = static_cast<Eigen::Index>(s.time_s.size());
  s.temperatures_c = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      temps.data(), n, static_cast<Eigen::Index>(s.temperature_names.size()));
  s.errors_um = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      errs.data(), n, static_cast<Eigen::Index>(s.error_names.size()));
  return s;
}

ThermalSeries ReadThermalSeriesCsv(const std::string& path) { return ParseThermalSeriesCsv(ReadTextFile(path), path); }

std::vector<ThermalSeries> ReadThermalSeriesFile(const std::string& path, std::vector<std::string>* warnings) {
  if (!IsZipFile(path)) return {ReadThermalSeriesCsv(path)};
  std::vector<ThermalSeries> out;
  std::vector<std::string> skipped;
  std::optional<InputError> first_error;
  for (const WorkbookSheet& sheet : ReadXlsxWorkbook(path)) {
    const std::string source = fmt::format("{}[{}]", path, sheet.name);
    bool empty = true;
    for (const auto& row : sheet.rows)
      for (const auto& cell : row) empty = empty && Trim(cell).empty();
    if (empty) continue;
    try {
      out.push_back(ParseThermalSeriesCsv(sheet.ToCsv(), source));
    } catch (const InputError& e) {
      if (!first_error) first_error = e;
      skipped.push_back(fmt::format("sheet '{}' of {} is not read as a recording: {}", sheet.name, path, e.what()));
    }
  }
  if (out.empty()) {
    if (first_error) throw *first_error;
    throw InputError(path, 0, "", "the workbook's sheets are all empty");
  }
  if (warnings) warnings->insert(warnings->end(), skipped.begin(), skipped.end());
  return out;
}

std::string FormatThermalSeriesCsv(const ThermalSeries& s) {
  std::string out;
  for (const auto& [k, v] : s.metadata) out += fmt::format("# {}: {}\n", k, v);
  std::vector<std::string> head;
  if (s.has_time) head.push_back("time_s");
  if (s.has_position) head.push_back("position_mm");
  if (s.has_spindle) head.push_back("spindle_rpm");
  if (s.has_coolant) head.push_back("coolant");
  for (const auto& t : s.temperature_names) head.push_back("t_" + t + "_c");
  for (const auto& e : s.error_names) head.push_back("e_" + e + "_um");
  out += fmt::format("{}\n", fmt::join(head, ","));
  auto cell = [](double v) { return std::isnan(v) ? std::string() : FormatShortest(v); };
  for (Eigen::Index r = 0; r < s.Rows(); ++r) {
    const auto ru = static_cast<std::size_t>(r);
    std::vector<std::string> f;
    if (s.has_time) f.push_back(FormatShortest(s.time_s[ru]));
    if (s.has_position) f.push_back(FormatShortest(s.position_mm[ru]));
    if (s.has_spindle) f.push_back(FormatShortest(s.spindle_rpm[ru]));
    if (s.has_coolant) f.push_back(std::string(CoolantStateName(s.coolant[ru])));
    for (Eigen::Index c = 0; c < s.temperatures_c.cols(); ++c) f.push_back(cell(s.temperatures_c(r, c)));
    for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) f.push_back(cell(s.errors_um(r, c)));
    out += fmt::format("{}\n", fmt::join(f, ","));
  }
  return out;
}

void WriteThermalSeriesCsv(const ThermalSeries& s, const std::string& path) {
  WriteTextFile(path, FormatThermalSeriesCsv(s));
}

ThermalSeries ImportFlThermalCsv(const std::string& path) {
  ThermalSeries s = ReadThermalSeriesCsv(path);
  auto require = [&](bool ok, const std::string& field, const std::string& why) {
    if (!ok) throw InputError(path, 1, field, why + " (fl_thermal layout: time_s, spindle_rpm, ch1_um..ch5_um, t1_C..t16_C)");
  };
  require(s.has_time, "time_s", "missing");
  require(s.has_spindle, "spindle_rpm", "missing");
  require(!s.has_position && !s.has_coolant, "", "unexpected position_mm/coolant column");
  require(s.error_names.size() == 5, "", fmt::format("{} displacement channels, expected 5", s.error_names.size()));
  require(s.temperature_names.size() == 16, "", fmt::format("{} temperatures, expected 16", s.temperature_names.size()));
  for (int i = 1; i <= 5; ++i) {
    std::string name = fmt::format("ch{}", i);
    require(s.ErrorIndex(name).has_value(), name + "_um", "missing");
  }
  for (int i = 1; i <= 16; ++i) {
    std::string name = fmt::format("t{}", i);
    require(s.TemperatureIndex(name).has_value(), name + "_C", "missing");
  }
  if (!s.metadata.count("source"))
    s.metadata["source"] = "CAIVIAC FL_THERMAL data/data.xlsx (MIT), spindle thermal drift 46 h";
  return s;
}

}  // namespace trueaxis::thermal
