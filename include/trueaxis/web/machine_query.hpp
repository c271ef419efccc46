#pragma once
// The shop overview's sort, filter and paging, done on the server so a browser shows a shop of
// hundreds or thousands of machines one page at a time. Pure.
#include <cstddef>
#include <string>
#include <vector>

#include "trueaxis/web/monitor_backend.hpp"

namespace trueaxis::web {

struct MachineQuery {
  std::string filter;        // case-insensitive substring of id, name, model revision, coolant or an alarm name
  std::string sort = "id";   // id | name | connected | alarms | revision | max_temp | max_correction
  bool descending = false;
  bool alarms_only = false;
  bool disconnected_only = false;
  std::size_t offset = 0;
  std::size_t limit = 200;
};

struct MachinePage {
  std::size_t total = 0;     // machines in the shop
  std::size_t matched = 0;   // after the filter
  std::vector<MachineSummary> machines;  // the page
};

// Throws std::invalid_argument naming the field for an unknown sort key.
MachinePage ApplyQuery(std::vector<MachineSummary> machines, const MachineQuery& query);
double MaxTemperatureC(const MachineSummary& m);     // NaN when none is known
double MaxAbsCorrectionUm(const MachineSummary& m);  // 0 when no axis

}  // namespace trueaxis::web
