#include "trueaxis/model/fit_input.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/measure/measurement_csv.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/sha256.hpp"

namespace trueaxis::model {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool StartsWith(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

// "coolant:flood" / "coolant-flood" / "coolant_flood" → "flood"; "" otherwise.
// Only a known coolant name counts, so "coolant-03" (a sequence) is not misread.
std::string CoolantFromLabel(const std::string& label) {
  const std::string l = Lower(label);
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
  const std::string l = Lower(std::string(Trim(label)));
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
  if (coolant.empty()) coolant = std::string(Trim(m.Meta("coolant").value_or("")));
  if (coolant.empty()) {
    coolant = CoolantFromLabel(s.label);
    field = "state";
  }
  if (coolant.empty() && Lower(s.label).rfind("coolant", 0) == 0)
    throw InputError(m.source, 0, "coolant",
                     fmt::format("state '{}' is a coolant state but does not say which coolant; add '# coolant: flood' "
                                 "(or mist/air)",
                                 s.label));
  if (!coolant.empty()) {
    auto c = ParseCoolantState(Lower(coolant));
    if (!c)
      throw InputError(m.source, 0, field,
                       fmt::format("unknown coolant state '{}' (expected off, flood, mist or air)", coolant));
    s.coolant = *c;
  }
  s.measurement = std::move(m);
  return s;
}

std::vector<FitState> LoadFitStates(const std::vector<std::string>& csv_paths, const std::string& manifest_path) {
  std::vector<FitState> out;
  for (const auto& p : csv_paths) {
    const std::string bytes = ReadTextFile(p);
    out.push_back(MakeFitState(measure::ParseMeasurementCsv(bytes, p), "", "", Sha256Hex(bytes)));
  }
  if (!manifest_path.empty()) {
    const std::string text = ReadTextFile(manifest_path);
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
      int line = 1;
      for (std::size_t i = 0; i < e.byte && i < text.size(); ++i)
        if (text[i] == '\n') ++line;
      throw InputError(manifest_path, line, "", std::string("not valid JSON: ") + e.what());
    }
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
    if (!list || !list->is_array())
      throw InputError(manifest_path, 0, "files", "expected an array of measurement files under \"files\"");
    if (list->empty()) throw InputError(manifest_path, 0, list_name, "lists no measurement files");
    const std::filesystem::path base = std::filesystem::path(manifest_path).parent_path();
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
      auto m = measure::ParseMeasurementCsv(bytes, p.string());
      std::string label = str("state");
      if (label.empty()) label = str("label");
      FitState s = MakeFitState(std::move(m), label, str("coolant"), Sha256Hex(bytes));
      if (const std::string axis = str("axis"); !axis.empty()) s.axis = axis;
      out.push_back(std::move(s));
    }
  }
  return out;
}

std::vector<FitState> LoadPreviousSources(const CompositeModel& previous, const std::string& model_path) {
  std::vector<FitState> out;
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
    FitState s = MakeFitState(measure::ParseMeasurementCsv(bytes, src.path), src.state, src.coolant, sha);
    if (!src.axis.empty()) s.axis = src.axis;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace trueaxis::model
