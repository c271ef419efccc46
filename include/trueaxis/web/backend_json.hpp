#pragma once
// JSON views of the MonitorBackend's records, as the web API sends them (docs/web.md, *Endpoints*).
// Non-finite numbers (a lost sensor) become null. A machine (MachineSummary) is written by
// runtime::MachineViewJson, the same writer as the workshop server's control API; its detail adds
// the model's label, the revisions that can be loaded and the before/after figures.
#include <nlohmann/json.hpp>

#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

nlohmann::json ToJson(const MachineDetail& m);
nlohmann::json ToJson(const LiveSeries& s);
nlohmann::json ToJson(const HistorySeries& s);
nlohmann::json ToJson(const AlarmEntry& a);
nlohmann::json ToJson(const AuditEntry& e);

}  // namespace trueaxis::web
