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

bool ParseTemperatureUnit(const std::string& text, TemperatureUnit* out) {
  if (text == "C" || text == "c" || text == "°C") *out = TemperatureUnit::kCelsius;
  else if (text == "F" || text == "f" || text == "°F") *out = TemperatureUnit::kFahrenheit;
  else if (text == "K" || text == "k") *out = TemperatureUnit::kKelvin;
  else return false;
  return true;
}

bool ParseErrorUnit(const std::string& text, ErrorUnit* out) {
  if (text == "um" || text == "µm") *out = ErrorUnit::kMicrometre;
  else if (text == "mm") *out = ErrorUnit::kMillimetre;
  else return false;
  return true;
}

std::optional<double> ParseTimeUnitS(const std::string& text) {
  if (text == "s") return 1.0;
  if (text == "min") return 60.0;
  if (text == "h") return 3600.0;
  return std::nullopt;
}

namespace {

// Seconds per unit of a recognised time column name (time_s, time_min, time_h), else 0.
double TimeColumnUnitS(const std::string& name) {
  if (name == "time_s") return 1;
  if (name == "time_min") return 60;
  if (name == "time_h") return 3600;
  return 0;
}

// The unit suffix of a mapped time column's name (…_s, …_min, …_h), else seconds.
double UnitOfMappedTimeColumn(const std::string& name) {
  for (const char* unit : {"min", "h", "s"})
    if (EndsWith(name, std::string("_") + unit)) return *ParseTimeUnitS(unit);
  return 1;
}

std::string ChannelNameOf(const std::string& column) {
  std::string out = column;
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  return out;
}

bool AllNumbers(const std::vector<std::string_view>& fields) {
  for (auto f : fields)
    if (!ParseDouble(f)) return false;
  return !fields.empty();
}

constexpr const char* kHeaderMissing =
    "the first row holds only numbers: the header seems missing; pass --no-header (columns are then named "
    "col1..colN, temperatures in °C unless named by --time-column or --error-column)";

double Median(std::vector<double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The recording-level unit checks (core/plausibility.hpp) of a parsed series whose units were not
// stated; then each temperature against the per-value limits. Columns are named by header.
void CheckUnits(ThermalSeries& s, const ThermalReadOptions& o, int header_line,
                const std::vector<std::string>& temperature_headers, const std::vector<std::string>& error_headers,
                const std::string& time_header, bool seconds_assumed, std::vector<std::string>* warnings) {
  const Eigen::Index n = s.Rows();
  const auto tc = s.temperatures_c.cols();
  if (o.temperature_unit == TemperatureUnit::kAuto && tc > 0) {
    double coolest = std::numeric_limits<double>::infinity();
    Eigen::Index coolest_col = 0;
    for (Eigen::Index c = 0; c < tc; ++c) {
      std::vector<double> v;
      for (Eigen::Index r = 0; r < n; ++r)
        if (std::isfinite(s.temperatures_c(r, c))) v.push_back(s.temperatures_c(r, c));
      const double m = Median(v);
      if (std::isfinite(m) && m < coolest) coolest = m, coolest_col = c;
    }
    if (auto why = SuspectTemperatureUnit(coolest))
      throw InputError(s.source, header_line, temperature_headers[static_cast<std::size_t>(coolest_col)],
                       fmt::format("temperatures are read as °C, but {}; pass --temperature-unit {} to convert, or "
                                   "--temperature-unit C if these really are °C",
                                   why.why, why.unit == SuspectedUnit::kKelvin ? "K" : "F"));
  }
  for (Eigen::Index c = 0; c < tc; ++c)
    for (Eigen::Index r = 0; r < n; ++r)
      if (std::isfinite(s.temperatures_c(r, c)))
        if (auto why = ImplausibleTemperatureC(s.temperatures_c(r, c)))
          throw InputError(s.source, s.LineOf(r), temperature_headers[static_cast<std::size_t>(c)],
                           *why + " (or pass --temperature-unit K or F)");
  if (o.error_unit == ErrorUnit::kAuto)
    for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
      double max_abs = 0, ss = 0;
      int count = 0;
      for (Eigen::Index r = 0; r < n; ++r)
        if (const double v = s.errors_um(r, c); std::isfinite(v)) max_abs = std::max(max_abs, std::abs(v)), ss += v * v, ++count;
      if (count < 2) continue;
      if (auto why = SuspectErrorUnit(max_abs, std::sqrt(ss / count)))
        throw InputError(s.source, header_line, error_headers[static_cast<std::size_t>(c)],
                         fmt::format("the error is read as µm, but {}; pass --error-unit mm to convert, or --error-unit "
                                     "um if these really are µm", why.why));
    }
  if (s.has_time && n >= 2 && seconds_assumed && warnings) {
    double largest = 0;
    for (Eigen::Index c = 0; c < tc; ++c) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (Eigen::Index r = 0; r < n; ++r)
        if (const double v = s.temperatures_c(r, c); std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
      if (hi >= lo) largest = std::max(largest, hi - lo);
    }
    if (auto why = SuspectTimeUnit(largest, s.time_s.back() - s.time_s.front()))
      warnings->push_back(fmt::format("{}: column '{}' is read as seconds, but {}; if it is not seconds, pass "
                                      "--time-unit min (or h)",
                                      s.source, time_header, why.why));
  }
}

}  // namespace

ThermalSeries ParseThermalSeriesCsv(std::string_view text, const std::string& source, const ThermalReadOptions& o,
                                    std::vector<std::string>* warnings) {
  ThermalSeries s;
  s.source = source;
  std::vector<Column> columns;
  std::vector<double> temps, errs;  // row-major while reading
  std::vector<std::string> temperature_headers, error_headers;
  std::string time_header;
  bool have_header = false;
  int header_line = 0;
  double time_unit_s = 1;
  double temperature_scale = 1, temperature_offset = 0;  // °C = scale * value + offset
  if (o.temperature_unit == TemperatureUnit::kFahrenheit) temperature_scale = 5.0 / 9.0, temperature_offset = -32 * 5.0 / 9.0;
  if (o.temperature_unit == TemperatureUnit::kKelvin) temperature_offset = -273.15;
  const double error_scale = o.error_unit == ErrorUnit::kMillimetre ? 1000.0 : 1.0;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  int line_no = 0;
  bool pending_data = false;  // --no-header: the line that gave the names is also the first data row
  std::vector<std::string_view> fields;
  while (pending_data || cursor.Next()) {
    if (!pending_data) {
      line_no = cursor.number();
      const std::string_view line = cursor.line();
      if (line.empty()) continue;
      if (line.front() == '#') {
        if (auto kv = ParseMetadataComment(line); kv && !have_header)
          s.metadata[std::string(kv->first)] = std::string(kv->second);
        continue;
      }
      fields = SplitCsvFields(line);
    }
    pending_data = false;
    if (!have_header) {
      have_header = true;
      header_line = line_no;
      std::vector<std::string> names;
      if (o.no_header) {
        for (std::size_t k = 0; k < fields.size(); ++k) names.push_back(fmt::format("col{}", k + 1));
        pending_data = true;
      } else {
        RefuseEmptyHeaderField(fields, source, line_no);
        for (auto f : fields) names.emplace_back(f);
      }
      const bool numeric_header = !o.no_header && AllNumbers(fields);
      auto is_error_column = [&](const std::string& name) {
        return std::find(o.error_columns.begin(), o.error_columns.end(), name) != o.error_columns.end();
      };
      for (const auto& mapped : o.error_columns)
        if (std::find(names.begin(), names.end(), mapped) == names.end())
          throw InputError(source, line_no, mapped,
                           numeric_header ? std::string(kHeaderMissing)
                                          : fmt::format("--error-column: no such column; the header has: {}",
                                                        fmt::join(names, ", ")));
      if (!o.time_column.empty() && std::find(names.begin(), names.end(), o.time_column) == names.end())
        throw InputError(source, line_no, o.time_column,
                         numeric_header ? std::string(kHeaderMissing)
                                        : fmt::format("--time-column: no such column; the header has: {}",
                                                      fmt::join(names, ", ")));
      std::set<std::string> seen;
      for (const std::string& name : names) {
        if (!seen.insert(name).second) throw InputError(source, line_no, name, "column given twice");
        Column col{Kind::kTime, name};
        // A temperature sensor or an error channel named `id`, read from this column.
        auto add = [&](Kind kind, const std::string& id) {
          const bool error = kind == Kind::kError;
          std::vector<std::string>& ids = error ? s.error_names : s.temperature_names;
          if (std::find(ids.begin(), ids.end(), id) != ids.end())
            throw InputError(source, line_no, name,
                             fmt::format("{} '{}' given twice", error ? "error channel" : "temperature", id));
          col.kind = kind;
          col.index = ids.size();
          ids.push_back(id);
          (error ? error_headers : temperature_headers).push_back(name);
        };
        const bool mapped_time = !o.time_column.empty() && name == o.time_column;
        if (mapped_time || (o.time_column.empty() && TimeColumnUnitS(name) > 0)) {
          if (s.has_time)
            throw InputError(source, line_no, name, fmt::format("a second time column (the first is '{}')", time_header));
          s.has_time = true;
          time_header = name;
          time_unit_s = o.time_unit_s > 0 ? o.time_unit_s : mapped_time ? UnitOfMappedTimeColumn(name) : TimeColumnUnitS(name);
        } else if (is_error_column(name)) {
          add(Kind::kError, ChannelNameOf(name));
        } else if (o.no_header) {
          add(Kind::kTemperature, name);
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
          add(Kind::kTemperature, sensor);
        } else if (EndsWith(name, "_um")) {
          std::string channel = name.substr(0, name.size() - 3);
          if (channel.rfind("e_", 0) == 0 && channel.size() > 2) channel = channel.substr(2);
          add(Kind::kError, channel);
        } else {
          throw InputError(source, line_no, name,
                           numeric_header
                               ? std::string(kHeaderMissing)
                               : std::string("unknown column; expected time_s (time_min, time_h), position_mm, "
                                             "spindle_rpm, coolant, t_<sensor>_c (or <sensor>_C) or e_<channel>_um (or "
                                             "<channel>_um); --error-column and --time-column map other names"));
        }
        columns.push_back(col);
      }
      if (s.temperature_names.empty())
        throw InputError(source, line_no, "", "no temperature column (t_<sensor>_c or <sensor>_C)");
      if (o.sample_interval_s > 0) {
        if (s.has_time)
          throw InputError(source, line_no, time_header,
                           "the file has a time column: leave out --sample-interval-s (it is for files without one)");
        if (!(std::isfinite(o.sample_interval_s)) || ImplausibleTimeS(o.sample_interval_s))
          throw InputError("command line", 0, "--sample-interval-s", "not a plausible interval in s");
        s.has_time = true;
      }
      continue;
    }
    if (fields.size() != columns.size())
      throw InputError(source, line_no, "",
                       fmt::format("{} fields, but the header has {} columns", fields.size(), columns.size()));
    const std::size_t row = s.source_line.size();
    s.source_line.push_back(line_no);
    temps.resize(temps.size() + s.temperature_names.size(), kNaN);
    errs.resize(errs.size() + s.error_names.size(), kNaN);
    double time = o.sample_interval_s > 0 ? static_cast<double>(row) * o.sample_interval_s : static_cast<double>(row);
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
          time = number("a finite time") * time_unit_s;
          if (auto why = ImplausibleTimeS(time)) throw InputError(source, line_no, col.header, *why);
          if (!s.time_s.empty() && !(time > s.time_s.back()))
            throw InputError(source, line_no, col.header,
                             fmt::format("time {} s is not after the previous row's {} s; rows must be in "
                                         "strictly increasing time",
                                         FormatShortest(time), FormatShortest(s.time_s.back())));
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
                             fmt::format("'{}' is not a temperature (empty or nan = not read)", f));
          // Checked once the whole column is read (CheckUnits): its unit is judged on all of it.
          temps[row * s.temperature_names.size() + col.index] = temperature_scale * *v + temperature_offset;
          break;
        }
        case Kind::kError: {
          if (IsMissing(f)) break;
          auto v = ParseDouble(f);
          if (!v || !std::isfinite(*v))
            throw InputError(source, line_no, col.header,
                             fmt::format("'{}' is not an error in {} (empty or nan = not measured)", f,
                                         o.error_unit == ErrorUnit::kMillimetre ? "mm" : "µm"));
          const double um = error_scale * *v;
          if (auto why = ImplausibleDeviationUm(um)) throw InputError(source, line_no, col.header, "thermal error " + *why);
          errs[row * s.error_names.size() + col.index] = um;
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
  const bool seconds_assumed = !time_header.empty() && o.time_unit_s == 0 && time_unit_s == 1;
  CheckUnits(s, o, header_line, temperature_headers, error_headers, time_header, seconds_assumed, warnings);
  return s;
}

ThermalSeries ReadThermalSeriesCsv(const std::string& path, const ThermalReadOptions& options,
                                   std::vector<std::string>* warnings) {
  return ParseThermalSeriesCsv(ReadTextFile(path), path, options, warnings);
}

std::vector<ThermalSeries> ReadThermalSeriesFile(const std::string& path, std::vector<std::string>* warnings,
                                                 const ThermalReadOptions& options) {
  if (!IsZipFile(path)) return {ReadThermalSeriesCsv(path, options, warnings)};
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
      out.push_back(ParseThermalSeriesCsv(sheet.ToCsv(), source, options, warnings));
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
