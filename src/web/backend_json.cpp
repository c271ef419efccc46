#include "trueaxis/web/backend_json.hpp"

#include <cmath>

namespace trueaxis::web {

using nlohmann::json;

namespace {
json Number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }
json Numbers(const std::vector<double>& v) {
  json a = json::array();
  for (double x : v) a.push_back(Number(x));
  return a;
}
json Traces(const std::vector<HistoryTrace>& traces) {
  json a = json::array();
  for (const auto& t : traces) {
    json times = json::array(), values = json::array();
    for (const auto& p : t.points) {
      times.push_back(p.unix_s);
      values.push_back(Number(p.value));
    }
    a.push_back({{"name", t.name}, {"unit", t.unit}, {"t", times}, {"v", values}});
  }
  return a;
}
}  // namespace

json ToJson(const MachineDetail& m) {
  json j = runtime::MachineViewJson(m.summary);
  json available = json::array(), figures = json::array();
  for (const auto& r : m.model.available)
    available.push_back({{"revision", r.revision}, {"sha256", r.sha256}, {"label", r.label},
                         {"loaded_unix_s", r.loaded_unix_s}});
  for (const auto& f : m.model.figures)
    figures.push_back({{"axis", f.axis}, {"quantity", f.quantity}, {"before_um", Number(f.before_um)},
                       {"after_um", Number(f.after_um)}, {"source", f.source}});
  j["model"]["label"] = m.model.label;
  j["model"]["available"] = available;
  j["model"]["figures"] = figures;
  return j;
}

json ToJson(const LiveSeries& s) {
  json samples = json::array();
  for (const auto& x : s.samples)
    samples.push_back({{"seq", x.sequence}, {"t", x.unix_s}, {"temp_c", Numbers(x.temp_c)},
                       {"correction_um", Numbers(x.correction_um)}});
  return {{"channels", s.channels}, {"axes", s.axes}, {"last_seq", s.last_sequence}, {"samples", samples}};
}

json ToJson(const HistorySeries& s) {
  return {{"from_unix_s", s.from_unix_s}, {"to_unix_s", s.to_unix_s}, {"decimated", s.decimated},
          {"temperatures", Traces(s.temperatures)}, {"corrections", Traces(s.corrections)}};
}

json ToJson(const AlarmEntry& a) {
  return {{"id", a.id},
          {"machine_id", a.machine_id},
          {"name", a.name},
          {"message", a.message},
          {"raised_unix_s", a.raised_unix_s},
          {"active", a.active},
          {"acknowledged", a.acknowledged},
          {"acknowledged_by", a.acknowledged_by},
          {"acknowledged_unix_s", a.acknowledged_unix_s}};
}

json ToJson(const AuditEntry& e) {
  return {{"id", e.id},         {"time_utc", e.time_utc}, {"user", e.user},     {"role", e.role},
          {"remote", e.remote}, {"action", e.action},     {"target", e.target}, {"detail", e.detail},
          {"outcome", e.outcome}};
}

}  // namespace trueaxis::web
