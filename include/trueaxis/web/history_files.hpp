#pragma once
// The history charts and exports of the pages, read from a history database (SQLite, read-only
// connections beside the writer that keeps writing). Shared by every backend that keeps one: one
// machine under `run` (all names) and the workshop server (names "machine/axis", selected by the
// machine's prefix, which the page does not show).
#include <cstddef>
#include <string>
#include <vector>

#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

struct HistorySelection {
  std::string db;                      // the SQLite file
  std::vector<std::string> channels;   // names as stored; empty = all
  std::vector<std::string> axes;       // names as stored; empty = all
  std::string strip_prefix;            // removed from the names shown ("vmc-07/")
};

// Traces evenly decimated to at most `max_points` points each (HistorySeries::decimated says so).
HistorySeries ReadHistorySeries(const HistorySelection& selection, double from_unix_s, double to_unix_s,
                                std::size_t max_points);

// `name`: the download's base name (the machine id).
ExportFile ExportHistory(const HistorySelection& selection, double from_unix_s, double to_unix_s, ExportFormat format,
                         const std::string& name);

}  // namespace trueaxis::web
