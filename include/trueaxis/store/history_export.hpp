#pragma once
// Export of the history database for people and spreadsheets (seed 000 names
// Excel): CSV per table, or one .xlsx workbook (libxlsxwriter) with a sheet
// per table plus an "info" sheet saying what was exported from where.
// Files are written to "<out>.tmp" and renamed, so a failed export never
// leaves half a file where a good one stood.
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/store/history_db.hpp"

namespace trueaxis::store {

enum class HistoryTable { kTemperature, kCompensation, kAlarm, kModelChange };
// "temperature", "compensation", "alarms", "models"
std::string_view HistoryTableName(HistoryTable t);
bool ParseHistoryTable(std::string_view name, HistoryTable* out);

struct ExportRequest {
  TimeRange range;
  std::vector<std::string> channels;  // temperature: empty = all
  std::vector<std::string> axes;      // compensation: empty = all
  // xlsx: data rows per sheet before continuing on "<table>_2"; Excel's limit
  // is 1,048,576 rows including the header. Lower only for tests.
  std::uint32_t max_rows_per_sheet = 1048575;
  // Temperature layout. Long (default): one row per reading,
  // time_s,time_utc,channel,raw_c,filtered_c,status. Wide: one row per
  // instant, time_s,time_utc,<ch>_c...,<ch>_status... with the filtered
  // values (blank where a channel has no reading at that instant) — the
  // shape a spreadsheet plots directly.
  bool wide = false;
};

struct ExportResult {
  std::int64_t temperature_rows = 0;
  std::int64_t compensation_rows = 0;
  std::int64_t alarm_rows = 0;
  std::int64_t model_change_rows = 0;
  std::string BriefReport() const;
};

// CSV of one table. Columns (temperature): time_s,time_utc,channel,raw_c,filtered_c,status.
ExportResult ExportCsv(const HistoryDb& db, HistoryTable table, const ExportRequest& request, const std::string& out_path);
// Workbook with sheets temperature, compensation, alarms, model_changes, info.
// A table longer than Excel's 1,048,576 rows continues on "temperature_2", ...
ExportResult ExportXlsx(const HistoryDb& db, const ExportRequest& request, const std::string& out_path);

}  // namespace trueaxis::store
