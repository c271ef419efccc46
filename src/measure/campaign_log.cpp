#include "trueaxis/measure/campaign_log.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"

namespace trueaxis::measure {

TemperatureLog ParseTemperatureLog(std::string_view text, const std::string& path, bool allow_no_rows) {
  TemperatureLog log;
  std::vector<int> col_sensor;  // per column: index into sensors, -1 other
  std::vector<std::string> col_travel;  // per column: the axis of a <axis>_travel_mm column, else empty
  int time_col = -1, coolant_col = -1;
  std::size_t columns = 0;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  while (cursor.Next()) {
    const std::string_view row = cursor.line();
    const int line = cursor.number();
    if (row.empty() || row[0] == '#') continue;
    const auto cells = SplitCsvFields(row);
    if (columns == 0) {  // header
      log.header_line = line;
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const std::string h(cells[c]);
        // A column twice would leave which one is read to the reader (the second one's values won).
        for (std::size_t before = 0; before < c; ++before)
          if (!h.empty() && cells[before] == cells[c])
            throw InputError(path, line, h, fmt::format("column given twice (columns {} and {})", before + 1, c + 1));
        if (h == "time_s") time_col = static_cast<int>(c);
        if (h == "coolant") coolant_col = static_cast<int>(c);
        const std::string travel_suffix = "_travel_mm";
        const bool travel = h.size() > travel_suffix.size() && h.substr(h.size() - travel_suffix.size()) == travel_suffix;
        col_travel.push_back(travel ? LowerAscii(h.substr(0, h.size() - travel_suffix.size())) : std::string());
        if (travel) log.travel_mm[col_travel.back()];
        if (h.size() > 4 && h.rfind("t_", 0) == 0 && h.substr(h.size() - 2) == "_c") {
          col_sensor.push_back(static_cast<int>(log.sensors.size()));
          log.sensors.push_back(h.substr(2, h.size() - 4));
        } else {
          col_sensor.push_back(-1);
        }
      }
      if (time_col < 0) throw InputError(path, line, "time_s", "the temperature log has no time_s column");
      columns = cells.size();
      continue;
    }
    if (cells.size() != columns)
      throw InputError(path, line, "", fmt::format("{} fields, but the header has {} columns (row cut short or "
                                                   "joined?)", cells.size(), columns));
    const auto t = ParseDouble(cells[static_cast<std::size_t>(time_col)]);
    if (!t || !std::isfinite(*t)) throw InputError(path, line, "time_s", "expected a number of seconds");
    if (!log.time_s.empty() && *t <= log.time_s.back())
      throw InputError(path, line, "time_s",
                       fmt::format("{} s is not after the previous row's {} s (the log must be in time order, one "
                                   "campaign per file)", *t, log.time_s.back()));
    std::vector<double> vals(log.sensors.size(), std::nan(""));
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (col_sensor[c] < 0 || cells[c].empty()) continue;  // empty: the hardware flagged the channel
      const std::string field = fmt::format("t_{}_c", log.sensors[col_sensor[c]]);
      const auto v = ParseDouble(cells[c]);
      if (!v) throw InputError(path, line, field, fmt::format("'{}' is not a number", cells[c]));
      if (auto why = ImplausibleTemperatureC(*v)) throw InputError(path, line, field, *why);
      vals[col_sensor[c]] = *v;
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (col_travel[c].empty()) continue;
      const auto v = cells[c].empty() ? std::optional<double>(std::nan("")) : ParseDouble(cells[c]);
      const std::string field = col_travel[c] + "_travel_mm";
      if (!v || std::isinf(*v) || *v < 0)
        throw InputError(path, line, field, fmt::format("'{}' is not a path length in mm (a number >= 0)", cells[c]));
      auto& series = log.travel_mm[col_travel[c]];
      if (!series.empty() && std::isfinite(series.back()) && std::isfinite(*v) && *v < series.back() - 1e-6)
        throw InputError(path, line, field,
                         fmt::format("{} mm is less than the previous row's {} mm: the travelled path only grows",
                                     FormatShortest(*v), FormatShortest(series.back())));
      series.push_back(*v);
    }
    if (coolant_col >= 0) {
      const std::string name(cells[static_cast<std::size_t>(coolant_col)]);
      const auto c = ParseCoolantState(name);
      if (!c) throw InputError(path, line, "coolant", fmt::format("unknown coolant state '{}'", name));
      log.coolant.push_back(*c);
    }
    log.time_s.push_back(*t);
    log.line.push_back(line);
    log.rows.push_back(std::move(vals));
  }
  if (columns == 0) throw InputError(path, cursor.number(), "", "no header line: the temperature log is empty");
  if (log.time_s.empty() && !allow_no_rows)
    throw InputError(path, cursor.number(), "time_s", "the temperature log has no rows");
  return log;
}


TemperatureLog ReadTemperatureLog(const std::string& path, bool allow_no_rows) {
  return ParseTemperatureLog(ReadTextFile(path), path, allow_no_rows);
}

int TemperatureLog::SensorIndex(std::string_view sensor) const {
  for (std::size_t i = 0; i < sensors.size(); ++i)
    if (sensors[i] == sensor) return static_cast<int>(i);
  return -1;
}

}  // namespace trueaxis::measure
