#include "trueaxis/web/machine_query.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>

namespace trueaxis::web {

namespace {
std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
bool Matches(const MachineSummary& m, const std::string& needle) {
  if (needle.empty()) return true;
  auto has = [&](const std::string& s) { return Lower(s).find(needle) != std::string::npos; };
  if (has(m.id) || has(m.name) || has(m.model.revision) || has(m.coolant)) return true;
  return std::any_of(m.alarms.begin(), m.alarms.end(), has);
}
// NaN sorts last in either order.
double OrLowest(double v) { return std::isnan(v) ? -std::numeric_limits<double>::infinity() : v; }
}  // namespace

double MaxTemperatureC(const MachineSummary& m) {
  double best = std::numeric_limits<double>::quiet_NaN();
  for (const auto& c : m.channels)
    if (std::isfinite(c.temp_c) && !(c.temp_c <= best)) best = c.temp_c;
  return best;
}

double MaxAbsCorrectionUm(const MachineSummary& m) {
  double best = 0;
  for (const auto& a : m.axes)
    if (std::isfinite(a.correction_um)) best = std::max(best, std::abs(a.correction_um));
  return best;
}

MachinePage ApplyQuery(std::vector<MachineSummary> machines, const MachineQuery& q) {
  using Less = std::function<bool(const MachineSummary&, const MachineSummary&)>;
  Less less;
  if (q.sort == "id") less = [](const auto& a, const auto& b) { return a.id < b.id; };
  else if (q.sort == "name") less = [](const auto& a, const auto& b) { return a.name < b.name; };
  else if (q.sort == "connected") less = [](const auto& a, const auto& b) { return a.connected < b.connected; };
  else if (q.sort == "alarms") less = [](const auto& a, const auto& b) { return a.alarms.size() < b.alarms.size(); };
  else if (q.sort == "revision") less = [](const auto& a, const auto& b) { return a.model.revision < b.model.revision; };
  else if (q.sort == "max_temp")
    less = [](const auto& a, const auto& b) { return OrLowest(MaxTemperatureC(a)) < OrLowest(MaxTemperatureC(b)); };
  else if (q.sort == "max_correction")
    less = [](const auto& a, const auto& b) { return MaxAbsCorrectionUm(a) < MaxAbsCorrectionUm(b); };
  else
    throw std::invalid_argument("sort: unknown key '" + q.sort +
                                "' (id, name, connected, alarms, revision, max_temp, max_correction)");
  MachinePage page;
  page.total = machines.size();
  const std::string needle = Lower(q.filter);
  std::erase_if(machines, [&](const MachineSummary& m) {
    return !Matches(m, needle) || (q.alarms_only && m.alarms.empty()) || (q.disconnected_only && m.connected);
  });
  page.matched = machines.size();
  std::stable_sort(machines.begin(), machines.end(), [&](const auto& a, const auto& b) {
    if (less(a, b)) return !q.descending;
    if (less(b, a)) return q.descending;
    return a.id < b.id;  // ties in a stable, readable order
  });
  const std::size_t from = std::min(q.offset, machines.size());
  const std::size_t to = std::min(machines.size(), from + q.limit);
  page.machines.assign(std::make_move_iterator(machines.begin() + from), std::make_move_iterator(machines.begin() + to));
  return page;
}

}  // namespace trueaxis::web
