#include "trueaxis/runtime/machine_view.hpp"

#include <cmath>

namespace trueaxis::runtime {

namespace {
nlohmann::json KnownOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json ModelViewJson(const MachineModelView& m) {
  return {{"revision", m.revision}, {"sha256", m.sha256}, {"file", m.file}};
}

nlohmann::json MachineViewJson(const MachineView& m) {
  nlohmann::json axes = nlohmann::json::array(), channels = nlohmann::json::array();
  for (const auto& a : m.axes)
    axes.push_back({{"name", a.name},
                    {"enabled", a.enabled},
                    {"state", a.state},
                    {"position_mm", KnownOrNull(a.position_mm)},
                    {"correction_um", KnownOrNull(a.correction_um)},
                    {"target_um", KnownOrNull(a.target_um)},
                    {"applied_um", KnownOrNull(a.applied_um)}});
  for (const auto& c : m.channels)
    channels.push_back({{"name", c.name}, {"temp_c", KnownOrNull(c.temp_c)}, {"health", c.health}});
  return {{"id", m.id},
          {"name", m.name},
          {"connected", m.connected},
          {"updated_unix_s", KnownOrNull(m.updated_unix_s)},
          {"alarms", m.alarms},
          {"coolant", m.coolant},
          {"coolant_override", m.coolant_override.empty() ? nlohmann::json(nullptr) : nlohmann::json(m.coolant_override)},
          {"model", ModelViewJson(m.model)},
          {"axes", axes},
          {"channels", channels}};
}

std::vector<std::string> SplitAlarmNames(const std::string& names) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos < names.size()) {
    const auto bar = names.find('|', pos);
    out.push_back(names.substr(pos, bar == std::string::npos ? std::string::npos : bar - pos));
    if (bar == std::string::npos) break;
    pos = bar + 1;
  }
  return out;
}

}  // namespace trueaxis::runtime
