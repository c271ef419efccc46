#include "trueaxis/signal/offline_filter.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::signal {
namespace {

}  // namespace

ReadingsTable ParseReadingsCsv(std::string_view text, const std::string& source, const std::vector<std::string>& channels) {
  ReadingsTable t;
  t.source = source;
  int time_col = -1;
  std::vector<int> column_to_channel;
  bool have_header = false;
  const std::string canonical = CanonicalCsv(text);  // ';' + decimal-comma exports read as CSV
  LineCursor cursor(canonical);
  int line_no = 0;
  double previous_time = -INFINITY;
  while (cursor.Next()) {
    line_no = cursor.number();
    const std::string_view line = cursor.line();
    if (line.empty() || line.front() == '#') continue;
    auto fields = SplitCsvFields(line);
    if (!have_header) {
      have_header = true;
      RefuseEmptyHeaderField(fields, source, line_no);
      for (std::size_t c = 0; c < fields.size(); ++c) {
        const std::string name(fields[c]);
        if (name == "time_s") {
          time_col = static_cast<int>(c);
          column_to_channel.push_back(-1);
          continue;
        }
        const bool wanted = channels.empty() || std::find(channels.begin(), channels.end(), name) != channels.end();
        if (wanted && std::find(t.channels.begin(), t.channels.end(), name) != t.channels.end())
          throw InputError(source, line_no, name, "column given twice");
        column_to_channel.push_back(wanted ? static_cast<int>(t.channels.size()) : -1);
        if (wanted) t.channels.push_back(name);
      }
      if (time_col < 0) throw InputError(source, line_no, "time_s", "missing: the readings need a time_s column");
      for (const auto& want : channels)
        if (std::find(t.channels.begin(), t.channels.end(), want) == t.channels.end())
          throw InputError(source, line_no, want, "no such column in the header");
      if (t.channels.empty()) throw InputError(source, line_no, "header", "no channel columns");
      t.values_c.assign(t.channels.size(), {});
      continue;
    }
    if (fields.size() != column_to_channel.size())
      throw InputError(source, line_no, "", fmt::format("{} fields, the header has {}", fields.size(), column_to_channel.size()));
    auto time = ParseDouble(fields[static_cast<std::size_t>(time_col)]);
    if (!time || !std::isfinite(*time)) throw InputError(source, line_no, "time_s", "not a number");
    if (auto why = ImplausibleTimeS(*time)) throw InputError(source, line_no, "time_s", *why);
    if (*time < previous_time)
      throw InputError(source, line_no, "time_s", fmt::format("{} goes back in time (previous row {})", *time, previous_time));
    previous_time = *time;
    t.time_s.push_back(*time);
    for (std::size_t c = 0; c < fields.size(); ++c) {
      const int ch = column_to_channel[c];
      if (ch < 0) continue;
      if (fields[c].empty()) {
        t.values_c[static_cast<std::size_t>(ch)].push_back(NAN);
        continue;
      }
      auto v = ParseDouble(fields[c]);
      if (!v) throw InputError(source, line_no, t.channels[static_cast<std::size_t>(ch)], fmt::format("'{}' is not a number", fields[c]));
      t.values_c[static_cast<std::size_t>(ch)].push_back(*v);
    }
  }
  if (!have_header) throw InputError(source, "empty file: no header row");
  if (t.time_s.empty()) throw InputError(source, "no readings after the header");
  return t;
}

ReadingsTable ReadReadingsCsv(const std::string& path, const std::vector<std::string>& channels) {
  return ParseReadingsCsv(ReadTextFile(path), path, channels);
}

OfflineFilterResult RunMonitorOffline(const ReadingsTable& table, const MonitorOptions& options,
                                      const CalibrationSet* calibration) {
  TemperatureMonitor mon(table.channels, options);
  OfflineFilterResult out;
  if (calibration) out.calibration_without_channel = mon.SetCalibration(*calibration);
  const std::size_t n = table.time_s.size(), channels = table.channels.size();
  out.channels = table.channels;
  out.filtered_c.assign(channels, std::vector<double>(n));
  out.status.assign(channels, std::vector<ChannelStatus>(n));
  out.summary.assign(channels, {});
  std::vector<hw::RawTemperature> raw(channels);
  std::vector<double> sum_sq(channels, 0.0);
  std::vector<std::size_t> ok_samples(channels, 0);
  for (std::size_t row = 0; row < n; ++row) {
    for (std::size_t c = 0; c < channels; ++c) {
      const double v = table.values_c[c][row];
      raw[c] = {v, !std::isfinite(v)};
    }
    mon.Update(table.time_s[row], raw);
    for (std::size_t c = 0; c < channels; ++c) {
      const auto& r = mon.reading(c);
      out.filtered_c[c][row] = r.filtered_c;
      out.status[c][row] = r.status;
      auto& s = out.summary[c];
      ++s.samples;
      s.spikes_rejected += r.spike_rejected;
      s.status_changes += r.status_changed;
      ++s.samples_in_status[static_cast<int>(r.status)];
      if (r.usable() && std::isfinite(r.calibrated_c)) {
        const double d = r.calibrated_c - r.filtered_c;
        s.max_abs_raw_minus_filtered_c = std::max(s.max_abs_raw_minus_filtered_c, std::abs(d));
        sum_sq[c] += d * d;
        ++ok_samples[c];
      }
    }
  }
  for (std::size_t c = 0; c < channels; ++c)
    if (ok_samples[c] > 0) out.summary[c].rms_raw_minus_filtered_c = std::sqrt(sum_sq[c] / ok_samples[c]);
  return out;
}

std::string OfflineFilterResult::FullReport() const {
  std::string out = fmt::format("{:<16} {:>8} {:>7} {:>8} {:>10} {:>10}  time in status\n", "channel", "samples",
                                "spikes", "changes", "rms(x-f)", "max|x-f|");
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const auto& s = summary[c];
    std::string statuses;
    for (int k = 0; k < kChannelStatusCount; ++k) {
      if (s.samples_in_status[k] == 0) continue;
      statuses += fmt::format("{}{} {:.1f}%", statuses.empty() ? "" : ", ", kChannelStatusNames[k],
                              100.0 * s.samples_in_status[k] / std::max<std::size_t>(s.samples, 1));
    }
    out += fmt::format("{:<16} {:>8} {:>7} {:>8} {:>8.3f} C {:>8.3f} C  {}\n", channels[c], s.samples, s.spikes_rejected,
                       s.status_changes, s.rms_raw_minus_filtered_c, s.max_abs_raw_minus_filtered_c, statuses);
  }
  return out;
}

std::string FormatOfflineFilterCsv(const ReadingsTable& table, const OfflineFilterResult& result) {
  std::string out = "time_s";
  for (const auto& c : result.channels) out += "," + c + "_c," + c + "_status";
  out += "\n";
  for (std::size_t row = 0; row < table.time_s.size(); ++row) {
    out += FormatShortest(table.time_s[row]);
    for (std::size_t c = 0; c < result.channels.size(); ++c) {
      const double v = result.filtered_c[c][row];
      out += ",";
      if (std::isfinite(v)) out += FormatShortest(std::round(v * 1e4) / 1e4);
      out += ",";
      out += ChannelStatusName(result.status[c][row]);
    }
    out += "\n";
  }
  return out;
}

}  // namespace trueaxis::signal
