#include "trueaxis/store/history_export.hpp"

#include <xlsxwriter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <unordered_map>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/store/time_text.hpp"

namespace trueaxis::store {

std::string_view HistoryTableName(HistoryTable t) {
  switch (t) {
    case HistoryTable::kTemperature: return "temperature";
    case HistoryTable::kCompensation: return "compensation";
    case HistoryTable::kAlarm: return "alarms";
    case HistoryTable::kModelChange: return "models";
  }
  return "?";
}

bool ParseHistoryTable(std::string_view name, HistoryTable* out) {
  for (auto t : {HistoryTable::kTemperature, HistoryTable::kCompensation, HistoryTable::kAlarm, HistoryTable::kModelChange}) {
    if (HistoryTableName(t) == name) {
      *out = t;
      return true;
    }
  }
  return false;
}

std::string ExportResult::BriefReport() const {
  return fmt::format("{} temperature readings, {} compensation values, {} alarms, {} model changes", temperature_rows,
                     compensation_rows, alarm_rows, model_change_rows);
}

namespace {

std::string Num(double v) { return std::isfinite(v) ? FormatShortest(v) : ""; }

// Fills TemporaryPathFor(path) and commits it on success (core/text_file.hpp).
class AtomicOutput {
 public:
  explicit AtomicOutput(std::string path) : path_(std::move(path)), tmp_(TemporaryPathFor(path_)) {
    out_.open(tmp_, std::ios::binary | std::ios::trunc);
    if (!out_) throw InputError(path_, "cannot create the export file (directory missing or not writable?)");
  }
  ~AtomicOutput() {
    if (!committed_) {
      out_.close();
      std::error_code ec;
      std::filesystem::remove(tmp_, ec);
    }
  }
  std::ofstream& stream() { return out_; }
  void Commit() {
    out_.close();
    if (!out_) throw std::runtime_error(path_ + ": write failed (disk full?)");
    committed_ = true;  // CommitTemporaryFile removes tmp_ whether it succeeds or not
    CommitTemporaryFile(tmp_, path_);
  }

 private:
  std::string path_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

// Groups the time-ordered readings by instant: one call per distinct time_s
// with the filtered value and status of each channel (NaN / "" where a
// channel has no reading then). Returns the number of readings seen.
std::int64_t ForEachInstant(const HistoryDb& db, const ExportRequest& req, const std::vector<std::string>& channels,
                            const std::function<void(double, const std::vector<double>&, const std::vector<std::string>&)>& fn) {
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < channels.size(); ++i) index[channels[i]] = i;
  std::vector<double> values(channels.size(), NAN);
  std::vector<std::string> statuses(channels.size());
  double current = NAN;
  bool pending = false;
  std::int64_t readings = 0;
  auto emit = [&] {
    if (!pending) return;
    fn(current, values, statuses);
    std::fill(values.begin(), values.end(), NAN);
    std::fill(statuses.begin(), statuses.end(), std::string());
    pending = false;
  };
  db.ForEachTemperature(req.range, req.channels, [&](const TemperatureRow& r) {
    if (pending && r.time_s != current) emit();
    current = r.time_s;
    const std::size_t i = index.at(r.channel);
    values[i] = r.filtered_c;
    statuses[i] = r.status;
    pending = true;
    ++readings;
  });
  emit();
  return readings;
}

std::vector<std::string> WideChannels(const HistoryDb& db, const ExportRequest& req) {
  return req.channels.empty() ? db.Channels() : req.channels;
}

}  // namespace

ExportResult ExportCsv(const HistoryDb& db, HistoryTable table, const ExportRequest& request, const std::string& out_path) {
  ExportResult result;
  AtomicOutput file(out_path);
  auto& out = file.stream();
  switch (table) {
    case HistoryTable::kTemperature:
      if (request.wide) {
        const auto channels = WideChannels(db, request);
        db.QueryTemperatures(TimeRange{1, 0}, request.channels);  // unknown names fail before any output
        out << "time_s,time_utc";
        for (const auto& c : channels) out << ',' << CsvField(c + "_c");
        for (const auto& c : channels) out << ',' << CsvField(c + "_status");
        out << '\n';
        result.temperature_rows = ForEachInstant(db, request, channels, [&](double t, const auto& values, const auto& statuses) {
          out << FormatShortest(t) << ',' << FormatUtc(t);
          for (double v : values) out << ',' << Num(v);
          for (const auto& st : statuses) out << ',' << CsvField(st);
          out << '\n';
        });
        break;
      }
      out << "time_s,time_utc,channel,raw_c,filtered_c,status\n";
      db.ForEachTemperature(request.range, request.channels, [&](const TemperatureRow& r) {
        out << FormatShortest(r.time_s) << ',' << FormatUtc(r.time_s) << ',' << CsvField(r.channel) << ','
            << Num(r.raw_c) << ',' << Num(r.filtered_c) << ',' << CsvField(r.status) << '\n';
        ++result.temperature_rows;
      });
      break;
    case HistoryTable::kCompensation:
      out << "time_s,time_utc,axis,position_mm,correction_um,state\n";
      db.ForEachCompensation(request.range, request.axes, [&](const CompensationRow& r) {
        out << FormatShortest(r.time_s) << ',' << FormatUtc(r.time_s) << ',' << CsvField(r.axis) << ','
            << Num(r.position_mm) << ',' << Num(r.correction_um) << ',' << CsvField(r.state) << '\n';
        ++result.compensation_rows;
      });
      break;
    case HistoryTable::kAlarm:
      out << "time_s,time_utc,severity,source,message\n";
      for (const auto& r : db.QueryAlarms(request.range)) {
        out << FormatShortest(r.time_s) << ',' << FormatUtc(r.time_s) << ',' << CsvField(r.severity) << ','
            << CsvField(r.source) << ',' << CsvField(r.message) << '\n';
        ++result.alarm_rows;
      }
      break;
    case HistoryTable::kModelChange:
      out << "time_s,time_utc,sha256,revision,note\n";
      for (const auto& r : db.QueryModelChanges(request.range)) {
        out << FormatShortest(r.time_s) << ',' << FormatUtc(r.time_s) << ',' << CsvField(r.sha256) << ','
            << CsvField(r.revision) << ',' << CsvField(r.note) << '\n';
        ++result.model_change_rows;
      }
      break;
  }
  file.Commit();
  return result;
}

namespace {

// A sheet that continues on "<name>_2", "<name>_3", ... when Excel's row limit is reached.
class SheetWriter {
 public:
  SheetWriter(lxw_workbook* wb, std::string name, std::vector<std::pair<std::string, double>> columns,
              lxw_format* header, lxw_format* time_format, lxw_row_t max_rows)
      : wb_(wb), name_(std::move(name)), columns_(std::move(columns)), header_(header), time_format_(time_format),
        max_rows_(std::clamp<lxw_row_t>(max_rows, 1, 1048575)) {
    NewSheet();
  }
  // Starts a row; returns the worksheet and the row index to write to.
  lxw_worksheet* Row(lxw_row_t* row) {
    if (next_row_ > max_rows_) NewSheet();
    *row = next_row_++;
    return ws_;
  }
  void Number(lxw_worksheet* ws, lxw_row_t row, lxw_col_t col, double v) {
    if (std::isfinite(v)) worksheet_write_number(ws, row, col, v, nullptr);
  }
  void Time(lxw_worksheet* ws, lxw_row_t row, lxw_col_t col, double time_s) {
    worksheet_write_number(ws, row, col, time_s, nullptr);
    // Excel serial date (days since 1899-12-30), shown as a UTC date-time.
    if (std::isfinite(time_s)) worksheet_write_number(ws, row, col + 1, time_s / 86400.0 + 25569.0, time_format_);
  }

 private:
  void NewSheet() {
    ++part_;
    const std::string sheet = part_ == 1 ? name_ : fmt::format("{}_{}", name_, part_);
    ws_ = workbook_add_worksheet(wb_, sheet.c_str());
    if (!ws_) throw std::runtime_error("cannot add worksheet " + sheet);
    for (std::size_t c = 0; c < columns_.size(); ++c) {
      worksheet_write_string(ws_, 0, static_cast<lxw_col_t>(c), columns_[c].first.c_str(), header_);
      worksheet_set_column(ws_, static_cast<lxw_col_t>(c), static_cast<lxw_col_t>(c), columns_[c].second, nullptr);
    }
    worksheet_freeze_panes(ws_, 1, 0);
    next_row_ = 1;
  }
  lxw_workbook* wb_;
  std::string name_;
  std::vector<std::pair<std::string, double>> columns_;
  lxw_format* header_;
  lxw_format* time_format_;
  lxw_row_t max_rows_;
  lxw_worksheet* ws_ = nullptr;
  lxw_row_t next_row_ = 1;
  int part_ = 0;
};

}  // namespace

ExportResult ExportXlsx(const HistoryDb& db, const ExportRequest& request, const std::string& out_path) {
  // Resolve names first so a bad --channels fails before any file exists.
  db.QueryTemperatures(TimeRange{1, 0}, request.channels);
  db.QueryCompensation(TimeRange{1, 0}, request.axes);

  ExportResult result;
  const std::string tmp = TemporaryPathFor(out_path);
  {
    // libxlsxwriter creates the file only when the workbook closes, after the whole export, and
    // then prints its own raw error: check that the file can be created before any work.
    std::ofstream probe(tmp, std::ios::binary | std::ios::trunc);
    if (!probe) throw InputError(out_path, "cannot create the export file (directory missing or not writable?)");
  }
  lxw_workbook_options options{};
  options.constant_memory = LXW_TRUE;  // rows stream to disk: exports of millions of readings stay small in memory
  lxw_workbook* wb = workbook_new_opt(tmp.c_str(), &options);
  if (!wb) throw InputError(out_path, "cannot create the workbook");
  bool closed = false;
  try {
    lxw_format* header = workbook_add_format(wb);
    format_set_bold(header);
    lxw_format* time_format = workbook_add_format(wb);
    format_set_num_format(time_format, "yyyy-mm-dd hh:mm:ss.000");

    if (request.wide) {
      const auto channels = WideChannels(db, request);
      std::vector<std::pair<std::string, double>> columns = {{"time_s", 16}, {"time_utc", 24}};
      for (const auto& c : channels) columns.emplace_back(c + "_c", 12);
      for (const auto& c : channels) columns.emplace_back(c + "_status", 14);
      SheetWriter wide(wb, "temperature", columns, header, time_format, request.max_rows_per_sheet);
      const auto n = static_cast<lxw_col_t>(channels.size());
      result.temperature_rows = ForEachInstant(db, request, channels, [&](double t, const auto& values, const auto& statuses) {
        lxw_row_t row;
        auto* ws = wide.Row(&row);
        wide.Time(ws, row, 0, t);
        for (lxw_col_t i = 0; i < n; ++i) {
          wide.Number(ws, row, 2 + i, values[i]);
          if (!statuses[i].empty()) worksheet_write_string(ws, row, 2 + n + i, statuses[i].c_str(), nullptr);
        }
      });
    }
    SheetWriter temps(wb, request.wide ? "temperature_long" : "temperature",
                      {{"time_s", 16}, {"time_utc", 24}, {"channel", 16}, {"raw_c", 10}, {"filtered_c", 10}, {"status", 16}},
                      header, time_format, request.max_rows_per_sheet);
    db.ForEachTemperature(request.range, request.channels, [&](const TemperatureRow& r) {
      lxw_row_t row;
      auto* ws = temps.Row(&row);
      temps.Time(ws, row, 0, r.time_s);
      worksheet_write_string(ws, row, 2, r.channel.c_str(), nullptr);
      temps.Number(ws, row, 3, r.raw_c);
      temps.Number(ws, row, 4, r.filtered_c);
      worksheet_write_string(ws, row, 5, r.status.c_str(), nullptr);
      if (!request.wide) ++result.temperature_rows;
    });
    SheetWriter comp(wb, "compensation",
                     {{"time_s", 16}, {"time_utc", 24}, {"axis", 8}, {"position_mm", 12}, {"correction_um", 14}, {"state", 12}},
                     header, time_format, request.max_rows_per_sheet);
    db.ForEachCompensation(request.range, request.axes, [&](const CompensationRow& r) {
      lxw_row_t row;
      auto* ws = comp.Row(&row);
      comp.Time(ws, row, 0, r.time_s);
      worksheet_write_string(ws, row, 2, r.axis.c_str(), nullptr);
      comp.Number(ws, row, 3, r.position_mm);
      comp.Number(ws, row, 4, r.correction_um);
      worksheet_write_string(ws, row, 5, r.state.c_str(), nullptr);
      ++result.compensation_rows;
    });
    SheetWriter alarms(wb, "alarms", {{"time_s", 16}, {"time_utc", 24}, {"severity", 10}, {"source", 16}, {"message", 60}},
                       header, time_format, request.max_rows_per_sheet);
    for (const auto& r : db.QueryAlarms(request.range)) {
      lxw_row_t row;
      auto* ws = alarms.Row(&row);
      alarms.Time(ws, row, 0, r.time_s);
      worksheet_write_string(ws, row, 2, r.severity.c_str(), nullptr);
      worksheet_write_string(ws, row, 3, r.source.c_str(), nullptr);
      worksheet_write_string(ws, row, 4, r.message.c_str(), nullptr);
      ++result.alarm_rows;
    }
    SheetWriter models(wb, "model_changes", {{"time_s", 16}, {"time_utc", 24}, {"sha256", 66}, {"revision", 16}, {"note", 40}},
                       header, time_format, request.max_rows_per_sheet);
    for (const auto& r : db.QueryModelChanges(request.range)) {
      lxw_row_t row;
      auto* ws = models.Row(&row);
      models.Time(ws, row, 0, r.time_s);
      worksheet_write_string(ws, row, 2, r.sha256.c_str(), nullptr);
      worksheet_write_string(ws, row, 3, r.revision.c_str(), nullptr);
      worksheet_write_string(ws, row, 4, r.note.c_str(), nullptr);
      ++result.model_change_rows;
    }
    lxw_worksheet* info = workbook_add_worksheet(wb, "info");
    worksheet_set_column(info, 0, 0, 20, nullptr);
    worksheet_set_column(info, 1, 1, 60, nullptr);
    auto channels_text = [&] {
      std::string s;
      for (const auto& c : request.channels) s += (s.empty() ? "" : ",") + c;
      return s.empty() ? std::string("all") : s;
    }();
    const std::pair<std::string, std::string> rows[] = {
        {"database", db.path()},
        {"schema_version", std::to_string(db.schema_version())},
        {"from", std::isfinite(request.range.from_s) ? FormatUtc(request.range.from_s) : "(start)"},
        {"to", std::isfinite(request.range.to_s) ? FormatUtc(request.range.to_s) : "(end)"},
        {"channels", channels_text},
        {"exported_at", FormatUtc(static_cast<double>(std::time(nullptr)))},
        {"time columns", "time_s: seconds since 1970-01-01T00:00:00Z; time_utc: the same as an Excel date-time (UTC)"},
    };
    lxw_row_t r = 0;
    for (const auto& [k, v] : rows) {
      worksheet_write_string(info, r, 0, k.c_str(), header);
      worksheet_write_string(info, r, 1, v.c_str(), nullptr);
      ++r;
    }
    closed = true;
    const lxw_error err = workbook_close(wb);
    if (err != LXW_NO_ERROR) throw InputError(out_path, fmt::format("cannot write workbook: {}", lxw_strerror(err)));
  } catch (...) {
    if (!closed) workbook_close(wb);
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
  CommitTemporaryFile(tmp, out_path);
  return result;
}

}  // namespace trueaxis::store
