#include "trueaxis/modelfit/fit_input.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/json_text.hpp"
#include "trueaxis/core/plausibility.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"
#include "trueaxis/measure/measurement_file.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/sha256.hpp"

namespace trueaxis::model {
namespace {

bool StartsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// "coolant:flood" / "coolant-flood" / "coolant_flood" → "flood"; "" otherwise.
// Only a known coolant name counts, so "coolant-03" (a sequence) is not misread.
std::string CoolantFromLabel(const std::string& label) {
  const std::string l = LowerAscii(label);
  for (const char* p : {"coolant:", "coolant-", "coolant_"})
    if (StartsWith(l, p)) {
      std::string rest = l.substr(std::string(p).size());
      // "coolant-flood-2" → "flood"
      const auto cut = rest.find_first_of("-_: ");
      rest = cut == std::string::npos ? rest : rest.substr(0, cut);
      return ParseCoolantState(rest) ? rest : "";
    }
  return "";
}

}  // namespace

const char* StateKindName(StateKind k) {
  switch (k) {
    case StateKind::kCold: return "cold";
    case StateKind::kHeated: return "heated";
    case StateKind::kAmbient: return "ambient";
    case StateKind::kUnknown: break;
  }
  return "unknown";
}

StateKind KindFromLabel(const std::string& label) {
  const std::string l = LowerAscii(std::string(Trim(label)));
  if (l.empty()) return StateKind::kUnknown;
  if (StartsWith(l, "cold")) return StateKind::kCold;
  if (StartsWith(l, "ambient")) return StateKind::kAmbient;
  return StateKind::kHeated;
}

FitState MakeFitState(measure::Measurement m, const std::string& label_override, const std::string& coolant_override,
                      const std::string& sha256) {
  FitState s;
  s.path = m.source;
  s.sha256 = sha256;
  s.label = label_override.empty() ? std::string(Trim(m.Meta("state").value_or(""))) : label_override;
  s.kind = KindFromLabel(s.label);
  // Campaigns number repeated states ("warm", sequence 3): make the label unique for reports.
  if (!s.label.empty())
    if (auto seq = ParseInt(Trim(m.Meta("sequence").value_or(""))))
      if (s.label.find_first_of("0123456789") == std::string::npos) s.label += fmt::format("-{:02}", *seq);
  s.axis = std::string(Trim(m.Meta("axis").value_or("")));
  std::string coolant = coolant_override;
  const char* field = "coolant";
  int field_line = 0;  // the file line the coolant came from (0: an option, or no line)
  if (coolant.empty()) {
    coolant = std::string(Trim(m.Meta("coolant").value_or("")));
    field_line = m.MetaLine("coolant");
  }
  if (coolant.empty()) {
    coolant = CoolantFromLabel(s.label);
    field = "state";
    field_line = label_override.empty() ? m.MetaLine("state") : 0;
  }
  if (coolant.empty() && LowerAscii(s.label).rfind("coolant", 0) == 0)
    throw InputError(m.source, field_line, "coolant",
                     fmt::format("state '{}' is a coolant state but does not say which coolant; add '# coolant: flood' "
                                 "(or mist/air)",
                                 s.label));
  if (!coolant.empty()) {
    auto c = ParseCoolantState(LowerAscii(coolant));
    if (!c)
      throw InputError(m.source, field_line, field,
                       fmt::format("unknown coolant state '{}' (expected off, flood, mist or air)", coolant));
    s.coolant = *c;
  }
  // A test measured through the compensation already has a correction in its deviations: a
  // model fitted on it would be the model's residual, not the machine's error.
  if (measure::CompensationActive(m).value_or(false))
    throw InputError(m.source, m.MetaLine("compensation"), "compensation",
                     "measured with the compensation on: its deviations already include a correction, and a model "
                     "fitted on them would not be the machine's error; fit tests measured with the compensation off "
                     "(if this one was, its line should read '# compensation: off')");
  s.measurement = std::move(m);
  return s;
}

namespace {

using measure::ReadTemperatureLog;
using measure::TemperatureLog;

// The rows of `log` in [start − window, start), mapped onto m's sensors.
TemperatureHistory HistoryBefore(const TemperatureLog& log, const measure::Measurement& m, double start_s) {
  TemperatureHistory h;
  std::vector<int> map;
  for (const auto& n : m.sensor_names) {
    auto it = std::find(log.sensors.begin(), log.sensors.end(), n);
    map.push_back(it == log.sensors.end() ? -1 : static_cast<int>(it - log.sensors.begin()));
  }
  for (std::size_t r = 0; r < log.time_s.size(); ++r) {
    const double rel = log.time_s[r] - start_s;
    if (rel >= 0 || rel < -TemperatureHistory::kWindowS) continue;
    std::vector<double> vals(map.size(), std::nan(""));
    for (std::size_t k = 0; k < map.size(); ++k)
      if (map[k] >= 0) vals[k] = log.rows[r][static_cast<std::size_t>(map[k])];
    h.time_s.push_back(rel);
    h.temps_c.push_back(std::move(vals));
    if (!log.coolant.empty()) h.coolant.push_back(log.coolant[r]);
  }
  // The axis's travel up to the measurement's end.
  const auto axis = m.Meta("axis");
  const auto travel = axis ? log.travel_mm.find(LowerAscii(*axis)) : log.travel_mm.end();
  if (travel != log.travel_mm.end()) {
    double end_s = 0;
    for (const auto& p : m.points)
      if (p.time_s) end_s = std::max(end_s, *p.time_s);
    for (std::size_t r = 0; r < log.time_s.size(); ++r) {
      const double rel = log.time_s[r] - start_s;
      if (rel < -TemperatureHistory::kWindowS || !std::isfinite(travel->second[r])) continue;
      h.travel_time_s.push_back(rel);
      h.travel_mm.push_back(travel->second[r]);
      if (rel > end_s) break;  // one row past the end: the last point lies between two rows
    }
  }
  return h;
}

// The log must reach the measurement's start (a log cut short would leave
// the lag without its history, silently) and must read what the measurement
// read at its start (another campaign's log does not).
void CheckLogBelongsTo(const TemperatureLog& log, const std::string& log_path, const measure::Measurement& m,
                       double start_s) {
  double step_s = 0;
  for (std::size_t r = 1; r < log.time_s.size(); ++r) step_s = std::max(step_s, log.time_s[r] - log.time_s[r - 1]);
  if (start_s > log.time_s.back() + 2 * step_s + 1)
    throw InputError(log_path, log.line.back(), "time_s",
                     fmt::format("the log ends at {} s, before {} starts at {} s on the log's clock: a truncated log "
                                 "or another campaign's", log.time_s.back(), m.source, start_s));
  if (start_s < log.time_s.front() - 2 * step_s - 1)
    throw InputError(log_path, log.line.front(), "time_s",
                     fmt::format("the log starts at {} s, after {} starts at {} s: another campaign's log?",
                                 log.time_s.front(), m.source, start_s));
  if (m.points.empty()) return;
  // The log row nearest the start against the measurement's first reading of each shared sensor.
  std::size_t nearest = 0;
  for (std::size_t r = 0; r < log.time_s.size(); ++r)
    if (std::abs(log.time_s[r] - start_s) < std::abs(log.time_s[nearest] - start_s)) nearest = r;
  constexpr double kToleranceC = 1.0;  // far above sensor noise, far below a day-to-day difference
  for (std::size_t k = 0; k < m.sensor_names.size(); ++k) {
    auto it = std::find(log.sensors.begin(), log.sensors.end(), m.sensor_names[k]);
    if (it == log.sensors.end()) continue;
    const double logged = log.rows[nearest][static_cast<std::size_t>(it - log.sensors.begin())];
    const double measured = m.points.front().temperatures_c.at(k);
    if (std::isfinite(logged) && std::isfinite(measured) && std::abs(logged - measured) > kToleranceC)
      throw InputError(log_path, log.line[nearest], "t_" + m.sensor_names[k] + "_c",
                       fmt::format("reads {:.2f} °C at {} s, but {} starts at {:.2f} °C: the log belongs to another "
                                   "campaign", logged, log.time_s[nearest], m.source, measured));
  }
}

// A manifest entry's axis and coolant are facts about the measurement: where the file's own
// metadata says otherwise, one of the two is wrong and the fit would build a bogus axis or use
// another coolant's states; refused, naming the manifest entry. A bad value is the manifest's.
void CheckEntryAgreesWithFile(const std::string& manifest_path, const std::string& where, const std::string& axis,
                              const std::string& coolant, const measure::Measurement& m) {
  const auto file_says = [&](const char* key) { return std::string(Trim(m.Meta(key).value_or(""))); };
  if (!axis.empty() && !file_says("axis").empty() && LowerAscii(std::string(Trim(axis))) != LowerAscii(file_says("axis")))
    throw InputError(manifest_path, 0, where + ".axis",
                     fmt::format("'{}', but {} line {} says '# axis: {}'", axis, m.source, m.MetaLine("axis"),
                                 file_says("axis")));
  if (coolant.empty()) return;
  const auto state = ParseCoolantState(LowerAscii(coolant));  // as MakeFitState reads it
  if (!state)
    throw InputError(manifest_path, 0, where + ".coolant",
                     fmt::format("unknown coolant state '{}' (expected off, flood, mist or air)", coolant));
  const auto file_state = ParseCoolantState(LowerAscii(file_says("coolant")));
  if (file_state && *file_state != *state)
    throw InputError(manifest_path, 0, where + ".coolant",
                     fmt::format("'{}', but {} line {} says '# coolant: {}'", coolant, m.source, m.MetaLine("coolant"),
                                 file_says("coolant")));
}

}  // namespace

TemperatureHistory TemperatureHistoryFromLog(const std::string& log_path, const measure::Measurement& m,
                                             double start_time_s, const std::vector<std::string>& required_sensors) {
  const TemperatureLog log = ReadTemperatureLog(log_path);
  for (const auto& name : required_sensors)
    if (std::find(log.sensors.begin(), log.sensors.end(), name) == log.sensors.end())
      throw InputError(log_path, log.header_line, fmt::format("t_{}_c", name),
                       fmt::format("the log has no column for the model's key sensor '{}': its history before {} "
                                   "would be missing and the lag would start from nothing", name, m.source));
  CheckLogBelongsTo(log, log_path, m, start_time_s);
  return HistoryBefore(log, m, start_time_s);
}

std::vector<FitState> LoadFitStates(const std::vector<std::string>& csv_paths, const std::string& given_manifest,
                                    const measure::MeasurementReadOptions& read) {
  std::vector<FitState> out;
  // A campaign's manifest.json given among the input files is read as a manifest.
  std::vector<std::string> manifests;
  for (const auto& p : csv_paths) {
    const std::string bytes = ReadTextFile(p);
    const auto first = bytes.find_first_not_of(" \t\r\n");
    if (first != std::string::npos && (bytes[first] == '{' || bytes[first] == '[')) {
      manifests.push_back(p);
      continue;
    }
    out.push_back(MakeFitState(measure::ParseMeasurement(bytes, p, read), "", "", Sha256Hex(bytes)));
  }
  if (!given_manifest.empty()) manifests.push_back(given_manifest);
  for (const auto& manifest_path : manifests) {
    const std::string text = ReadTextFile(manifest_path);
    const nlohmann::json doc = ParseJsonOrThrow(text, manifest_path);
    // Accept {"files": [...]} (also "measurements"/"states") or a bare array.
    const nlohmann::json* list = nullptr;
    std::string list_name = "files";
    if (doc.is_array()) {
      list = &doc;
      list_name = "";
    } else if (doc.is_object()) {
      for (const char* key : {"files", "measurements", "states"})
        if (doc.contains(key)) {
          list = &doc[key];
          list_name = key;
          break;
        }
    }
    measure::CheckCampaignManifestFormat(doc, manifest_path);
    if (!list || !list->is_array())
      throw InputError(manifest_path, 0, "files", "expected an array of measurement files under \"files\"");
    if (list->empty()) throw InputError(manifest_path, 0, list_name, "lists no measurement files");
    const std::filesystem::path base = std::filesystem::path(manifest_path).parent_path();
    // The sim campaign's temperature log: the history before each measurement (thermal lag).
    std::optional<TemperatureLog> log;
    std::string log_path, log_sha;
    if (doc.is_object() && doc.contains("temperature_log")) {
      if (!doc["temperature_log"].is_string())
        throw InputError(manifest_path, 0, "temperature_log", "expected a file name");
      std::filesystem::path lp(doc["temperature_log"].get<std::string>());
      if (lp.is_relative()) lp = base / lp;
      if (!std::filesystem::exists(lp))
        throw InputError(manifest_path, 0, "temperature_log", fmt::format("'{}' does not exist", lp.string()));
      log_path = lp.string();
      log = ReadTemperatureLog(log_path);
      log_sha = Sha256Hex(ReadTextFile(log_path));
    }
    for (std::size_t i = 0; i < list->size(); ++i) {
      const auto& e = (*list)[i];
      const std::string where = fmt::format("{}[{}]", list_name, i);
      std::string rel;
      if (e.is_string()) rel = e.get<std::string>();
      else if (e.is_object()) {
        for (const char* key : {"path", "file", "csv"})
          if (e.contains(key) && e[key].is_string()) {
            rel = e[key].get<std::string>();
            break;
          }
      }
      if (rel.empty()) throw InputError(manifest_path, 0, where + ".path", "each entry needs a \"path\" string");
      auto str = [&](const char* key) -> std::string {
        if (!e.is_object() || !e.contains(key)) return "";
        if (!e[key].is_string())
          throw InputError(manifest_path, 0, fmt::format("{}.{}", where, key), "expected a string");
        return e[key].get<std::string>();
      };
      std::filesystem::path p(rel);
      if (p.is_relative()) p = base / p;
      const std::string bytes = ReadTextFile(p.string());
      auto m = measure::ParseMeasurement(bytes, p.string(), read);
      std::string label = str("state");
      if (label.empty()) label = str("label");
      const std::string coolant = str("coolant");
      const std::string axis = str("axis");
      CheckEntryAgreesWithFile(manifest_path, where, axis, coolant, m);
      FitState s = MakeFitState(std::move(m), label, coolant, Sha256Hex(bytes));
      if (!axis.empty()) s.axis = axis;
      if (log && e.is_object() && e.contains("start_time_s") && !e["start_time_s"].is_null()) {
        if (!e["start_time_s"].is_number())
          throw InputError(manifest_path, 0, where + ".start_time_s", "expected a number of seconds");
        s.start_time_s = e["start_time_s"].get<double>();
        // As predict --temperature-log: another campaign's log, one cut short or a start outside it
        // would give the lag a wrong or no history, silently.
        CheckLogBelongsTo(*log, log_path, s.measurement, s.start_time_s);
        s.history = HistoryBefore(*log, s.measurement, s.start_time_s);
        s.temperature_log = log_path;
        s.temperature_log_sha256 = log_sha;
      }
      out.push_back(std::move(s));
    }
  }
  RejectDuplicateStates(out);
  return out;
}

void RejectDuplicateStates(const std::vector<FitState>& states) {
  std::map<std::string, const FitState*> seen;
  for (const auto& s : states) {
    if (s.sha256.empty()) continue;
    auto [it, fresh] = seen.emplace(s.sha256, &s);
    if (!fresh)
      throw InputError(s.path, 0, "file",
                       it->second->path == s.path
                           ? std::string("given twice: each measurement may enter the fit once")
                           : fmt::format("has the same bytes as {}: the same measurement given twice would count "
                                         "twice in the fit", it->second->path));
  }
}

std::vector<FitState> LoadPreviousSources(const CompositeModel& previous, const std::string& model_path,
                                          const measure::MeasurementReadOptions& read) {
  std::vector<FitState> out;
  std::map<std::string, TemperatureLog> logs;
  for (std::size_t i = 0; i < previous.sources.size(); ++i) {
    const auto& src = previous.sources[i];
    if (!std::filesystem::exists(src.path))
      throw InputError(model_path, 0, fmt::format("sources[{}].path", i),
                       fmt::format("'{}' (a source of the previous fit) no longer exists", src.path));
    const std::string bytes = ReadTextFile(src.path);
    const std::string sha = Sha256Hex(bytes);
    if (!src.sha256.empty() && sha != src.sha256)
      throw InputError(src.path, 0, "sha256",
                       fmt::format("the file changed since the previous fit (recorded {}…, now {}…); re-fit from the "
                                   "files explicitly if the change is intended",
                                   src.sha256.substr(0, 12), sha.substr(0, 12)));
    FitState s = MakeFitState(measure::ParseMeasurement(bytes, src.path, read), src.state, src.coolant, sha);
    if (!src.axis.empty()) s.axis = src.axis;
    if (!src.temperature_log.empty() && std::isfinite(src.start_time_s)) {
      // The history (thermal lag) the previous fit had: the same log, hash-checked.
      auto it = logs.find(src.temperature_log);
      if (it == logs.end()) {
        const std::string where = fmt::format("sources[{}].temperature_log", i);
        if (!std::filesystem::exists(src.temperature_log))
          throw InputError(model_path, 0, where,
                           fmt::format("'{}' (the temperature log of the previous fit) no longer exists",
                                       src.temperature_log));
        const std::string log_sha = Sha256Hex(ReadTextFile(src.temperature_log));
        if (!src.temperature_log_sha256.empty() && log_sha != src.temperature_log_sha256)
          throw InputError(src.temperature_log, 0, "sha256", "the temperature log changed since the previous fit");
        it = logs.emplace(src.temperature_log, ReadTemperatureLog(src.temperature_log)).first;
      }
      CheckLogBelongsTo(it->second, src.temperature_log, s.measurement, src.start_time_s);
      s.history = HistoryBefore(it->second, s.measurement, src.start_time_s);
      s.temperature_log = src.temperature_log;
      s.temperature_log_sha256 = src.temperature_log_sha256;
      s.start_time_s = src.start_time_s;
    }
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace trueaxis::model
