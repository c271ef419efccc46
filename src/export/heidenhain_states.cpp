#include "trueaxis/export/heidenhain_states.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/number_text.hpp"
#include "trueaxis/export/heidenhain_table.hpp"

namespace trueaxis::exporter {
namespace {
std::string Upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}
}  // namespace

std::vector<HeidenhainState> HeidenhainModelStates(const model::AxisModel& axis, const ResampleOptions& ro,
                                                   const std::string& source) {
  std::vector<HeidenhainState> states;
  const bool frozen = !ro.thermal.temperatures_c.empty();
  ResampleOptions cold = ro;
  cold.thermal.temperatures_c.clear();
  cold.thermal.coolant = CoolantState::kOff;
  states.push_back({"COLD", "cold state, coolant off", ResampleModel(axis, cold, source).table, !frozen});
  if (!frozen) return states;
  std::set<CoolantState> fitted;
  for (const auto& d : axis.directions)
    for (const auto& g : d.thermal) fitted.insert(g.coolant);
  // A coolant the model covers with one set of gains and its memory (key_loss_s):
  // with the temperatures frozen its table uses those gains.
  for (std::size_t c = 0; c < axis.key_loss_s.size(); ++c)
    if (!axis.key_loss_s[c].empty()) fitted.insert(static_cast<CoolantState>(c));
  if (fitted.empty()) fitted.insert(CoolantState::kOff);
  std::string temps;
  for (const auto& [n, v] : ro.thermal.temperatures_c) temps += fmt::format(" {}={}", n, FormatShortest(v));
  for (CoolantState c : fitted) {
    ResampleOptions o = ro;
    o.thermal.coolant = c;
    states.push_back({Upper(std::string(CoolantStateName(c))), fmt::format("coolant {},{}", CoolantStateName(c), temps),
                      ResampleModel(axis, o, source).table, c == ro.thermal.coolant});
  }
  return states;
}

std::vector<HeidenhainFile> WriteHeidenhainSet(const std::vector<HeidenhainState>& states, const std::string& axis,
                                               const std::string& cma_file_name, ValueSign sign,
                                               const std::string& generator) {
  const std::string stem = Upper(std::filesystem::path(cma_file_name).stem().string());
  std::vector<HeidenhainFile> files;
  std::vector<CmaLine> lines;
  for (const auto& s : states) {
    const std::string com = fmt::format("{}_{}.COM", stem, s.name);
    CompensationTable t = s.table;
    t.axis = axis;
    files.push_back({com, WriteHeidenhainCom(t, com, sign, generator)});
    lines.push_back({com, s.active, s.description});
  }
  files.push_back({cma_file_name, WriteHeidenhainCma(axis, cma_file_name, lines, generator)});
  return files;
}

}  // namespace trueaxis::exporter
