// trueaxis history: read the temperature history database (docs/history.md).
//   trueaxis history info   --db FILE
//   trueaxis history query  --db FILE [--from T] [--to T] [--channels a,b] [--table temperature|compensation|alarms|models] [--limit N]
//   trueaxis history export --db FILE [--from T] [--to T] [--channels a,b] --format csv|xlsx --out PATH [--table ...]
// T is seconds since the Unix epoch or ISO 8601 UTC (2026-11-22T08:00:00Z).
// The database is opened read-only: these commands never change it.
#include <cmath>
#include <memory>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/output_path.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_export.hpp"
#include "trueaxis/store/time_text.hpp"

namespace {

using namespace trueaxis::store;
using trueaxis::InputError;

struct HistoryOptions {
  std::string db;
  std::string from, to;
  std::string channels;
  std::string table = "temperature";
  std::string format;
  std::string out;
  std::size_t limit = 0;
  std::string layout = "long";
};

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    auto pos = text.find(',', start);
    auto item = trueaxis::Trim(std::string_view(text).substr(start, pos == std::string::npos ? std::string::npos : pos - start));
    if (!item.empty()) out.emplace_back(item);
    if (pos == std::string::npos) break;
    start = pos + 1;
  }
  return out;
}

ExportRequest MakeRequest(const HistoryOptions& o, HistoryTable table) {
  ExportRequest r;
  auto parse = [](const std::string& text, const char* field, double fallback) {
    if (text.empty()) return fallback;
    auto v = ParseTimeText(text);
    if (!v)
      throw InputError("command line", 0, field,
                       fmt::format("'{}' is not a time: give seconds since 1970 or ISO 8601 UTC like 2026-11-22T08:00:00Z", text));
    return *v;
  };
  r.range.from_s = parse(o.from, "--from", -INFINITY);
  r.range.to_s = parse(o.to, "--to", INFINITY);
  if (r.range.from_s > r.range.to_s)
    throw InputError("command line", 0, "--to", fmt::format("'{}' is before --from '{}'", o.to, o.from));
  // --channels names temperature channels, or axes for the compensation table.
  if (table == HistoryTable::kCompensation) r.axes = SplitList(o.channels);
  else r.channels = SplitList(o.channels);
  return r;
}

HistoryTable Table(const std::string& name) {
  HistoryTable t;
  if (!ParseHistoryTable(name, &t))
    throw InputError("command line", 0, "--table",
                     fmt::format("unknown table '{}' (temperature, compensation, alarms, models)", name));
  return t;
}

std::string Num(double v) { return std::isfinite(v) ? trueaxis::FormatShortest(v) : ""; }

void RunInfo(const HistoryOptions& o) {
  HistoryDb db(o.db, HistoryDb::Mode::kReadOnly);
  fmt::print("{}", db.Summary().BriefReport());
}

void RunQuery(const HistoryOptions& o) {
  const HistoryTable table = Table(o.table);
  const ExportRequest req = MakeRequest(o, table);
  HistoryDb db(o.db, HistoryDb::Mode::kReadOnly);
  std::size_t n = 0;
  // The CSV header goes out with the first row (or at the end when there is none), so a database that
  // turns out damaged on its first page prints no header before its error.
  std::string header;
  bool header_printed = false;
  auto print_header = [&] {
    if (!header_printed) fmt::print("{}", header);
    header_printed = true;
  };
  auto more = [&] { return o.limit == 0 || n < o.limit; };
  // Stops a row walk once --limit rows are printed (no need to scan the rest of a big database).
  struct LimitReached {};
  auto stop_if_done = [&] {
    if (!more()) throw LimitReached{};
  };
  try {
  switch (table) {
    case HistoryTable::kTemperature:
      header = "time_s,time_utc,channel,raw_c,filtered_c,status\n";
      db.ForEachTemperature(req.range, req.channels, [&](const TemperatureRow& r) {
        stop_if_done();
        ++n;
        print_header();
        fmt::print("{},{},{},{},{},{}\n", Num(r.time_s), FormatUtc(r.time_s), trueaxis::CsvField(r.channel), Num(r.raw_c),
                   Num(r.filtered_c), trueaxis::CsvField(r.status));
      });
      break;
    case HistoryTable::kCompensation:
      header = "time_s,time_utc,axis,position_mm,correction_um,state\n";
      db.ForEachCompensation(req.range, req.axes, [&](const CompensationRow& r) {
        stop_if_done();
        ++n;
        print_header();
        fmt::print("{},{},{},{},{},{}\n", Num(r.time_s), FormatUtc(r.time_s), trueaxis::CsvField(r.axis), Num(r.position_mm),
                   Num(r.correction_um), trueaxis::CsvField(r.state));
      });
      break;
    case HistoryTable::kAlarm:
      header = "time_s,time_utc,severity,source,message\n";
      for (const auto& r : db.QueryAlarms(req.range)) {
        if (!more()) break;
        ++n;
        print_header();
        fmt::print("{},{},{},{},{}\n", Num(r.time_s), FormatUtc(r.time_s), trueaxis::CsvField(r.severity), trueaxis::CsvField(r.source), trueaxis::CsvField(r.message));
      }
      break;
    case HistoryTable::kModelChange:
      header = "time_s,time_utc,sha256,revision,note\n";
      for (const auto& r : db.QueryModelChanges(req.range)) {
        if (!more()) break;
        ++n;
        print_header();
        fmt::print("{},{},{},{},{}\n", Num(r.time_s), FormatUtc(r.time_s), trueaxis::CsvField(r.sha256), trueaxis::CsvField(r.revision), trueaxis::CsvField(r.note));
      }
      break;
  }
  } catch (const LimitReached&) {
  }
  print_header();
}

void RunExport(const HistoryOptions& o) {
  if (o.format != "csv" && o.format != "xlsx")
    throw InputError("command line", 0, "--format", fmt::format("'{}' is not csv or xlsx", o.format));
  const HistoryTable table = Table(o.table);
  ExportRequest req = MakeRequest(o, table);
  if (o.layout != "long" && o.layout != "wide")
    throw InputError("command line", 0, "--layout", fmt::format("'{}' is not long or wide", o.layout));
  req.wide = o.layout == "wide";
  trueaxis::RefuseOutputOverInput(o.out, {o.db}, "--out");
  trueaxis::RefuseUnwritableOutputFile(o.out, "--out");
  HistoryDb db(o.db, HistoryDb::Mode::kReadOnly);
  const ExportResult result = o.format == "csv" ? ExportCsv(db, table, req, o.out) : ExportXlsx(db, req, o.out);
  fmt::print("exported {} to {}\n", result.BriefReport(), o.out);
}

void AddRangeOptions(CLI::App* cmd, HistoryOptions& o) {
  cmd->add_option("--db", o.db, "history database (SQLite)")->required();
  cmd->add_option("--from", o.from, "start time, inclusive: seconds since 1970 or ISO 8601 UTC");
  cmd->add_option("--to", o.to, "end time, inclusive");
  cmd->add_option("--channels", o.channels, "comma-separated channel names (axes for --table compensation); default all");
  cmd->add_option("--table", o.table, "temperature (default), compensation, alarms or models");
}

void Setup(CLI::App& app) {
  auto* history = app.add_subcommand("history", "Query and export the temperature/compensation history database");
  history->require_subcommand(1);

  auto info = std::make_shared<HistoryOptions>();
  auto* info_cmd = history->add_subcommand("info", "Summarise a history database: tables, time span, channels");
  info_cmd->add_option("--db", info->db, "history database (SQLite)")->required();
  info_cmd->callback([info] { RunInfo(*info); });

  auto query = std::make_shared<HistoryOptions>();
  auto* query_cmd = history->add_subcommand("query", "Print rows of a time range as CSV on stdout");
  AddRangeOptions(query_cmd, *query);
  query_cmd->add_option("--limit", query->limit, "print at most N rows (0: all)");
  query_cmd->callback([query] { RunQuery(*query); });

  auto exp = std::make_shared<HistoryOptions>();
  auto* export_cmd = history->add_subcommand("export", "Export a time range to CSV (one table) or Excel .xlsx (all tables)");
  AddRangeOptions(export_cmd, *exp);
  export_cmd->add_option("--format", exp->format, "csv or xlsx")->required();
  export_cmd->add_option("--out", exp->out, "file to write")->required();
  export_cmd->add_option("--layout", exp->layout,
                         "temperature layout: long (a row per reading, default) or wide (a row per instant, a column per channel)");
  export_cmd->callback([exp] { RunExport(*exp); });
}

trueaxis::cli::CommandRegistrar reg("history", Setup);

}  // namespace
