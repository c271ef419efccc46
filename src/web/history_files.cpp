#include "trueaxis/web/history_files.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_export.hpp"
#include "trueaxis/web/password_hash.hpp"

namespace trueaxis::web {

namespace fs = std::filesystem;

namespace {
// Keeps at most `max_points` of a trace, evenly spaced (every k-th point).
bool Decimate(std::vector<HistoryPoint>& points, std::size_t max_points) {
  if (max_points == 0 || points.size() <= max_points) return false;
  const std::size_t stride = (points.size() + max_points - 1) / max_points;
  std::vector<HistoryPoint> kept;
  for (std::size_t i = 0; i < points.size(); i += stride) kept.push_back(points[i]);
  points = std::move(kept);
  return true;
}

std::string Shown(const std::string& stored, const std::string& prefix) {
  return !prefix.empty() && stored.rfind(prefix, 0) == 0 ? stored.substr(prefix.size()) : stored;
}
}  // namespace

HistorySeries ReadHistorySeries(const HistorySelection& s, double from, double to, std::size_t max_points) {
  const store::HistoryDb db(s.db, store::HistoryDb::Mode::kReadOnly);
  HistorySeries h{from, to, {}, {}, false};
  std::map<std::string, std::vector<HistoryPoint>> temps, corrs;
  const store::TimeRange range{from, to};
  db.ForEachTemperature(range, s.channels, [&](const store::TemperatureRow& r) {
    temps[Shown(r.channel, s.strip_prefix)].push_back({r.time_s, r.filtered_c});
  });
  db.ForEachCompensation(range, s.axes, [&](const store::CompensationRow& r) {
    corrs[Shown(r.axis, s.strip_prefix)].push_back({r.time_s, r.correction_um});
  });
  for (auto& [name, points] : temps) {
    h.decimated |= Decimate(points, max_points);
    h.temperatures.push_back({name, "C", std::move(points)});
  }
  for (auto& [name, points] : corrs) {
    h.decimated |= Decimate(points, max_points);
    h.corrections.push_back({name, "um", std::move(points)});
  }
  return h;
}

ExportFile ExportHistory(const HistorySelection& s, double from, double to, ExportFormat format, const std::string& name) {
  const store::HistoryDb db(s.db, store::HistoryDb::Mode::kReadOnly);
  const bool xlsx = format == ExportFormat::kXlsx;
  const fs::path tmp = fs::temp_directory_path() / ("trueaxis-web-export-" + RandomToken(8) + (xlsx ? ".xlsx" : ".csv"));
  store::ExportRequest request;
  request.range = {from, to};
  request.channels = s.channels;
  request.axes = s.axes;
  std::string file = name;
  if (xlsx) {
    store::ExportXlsx(db, request, tmp.string());
  } else if (format == ExportFormat::kCsvTemperature) {
    request.wide = true;
    store::ExportCsv(db, store::HistoryTable::kTemperature, request, tmp.string());
    file += "_temperature";
  } else {
    store::ExportCsv(db, store::HistoryTable::kCompensation, request, tmp.string());
    file += "_compensation";
  }
  std::ifstream in(tmp, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  in.close();
  std::error_code ec;
  fs::remove(tmp, ec);
  return {file + (xlsx ? ".xlsx" : ".csv"),
          xlsx ? "application/vnd.openxmlformats-officedocument.spreadsheetml.sheet" : "text/csv; charset=utf-8",
          bytes.str()};
}

}  // namespace trueaxis::web
