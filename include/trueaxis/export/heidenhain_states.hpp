#pragma once
// The HEIDENHAIN set of one axis: a .COM table per thermal state and the .CMA
// that switches between them (heidenhain_table.hpp has the file formats).
// For a model: COLD (no thermal part, coolant off) and, when a thermal state is
// frozen (--temp), one table per coolant state the model has gains for, the
// requested coolant ACTIVE. For a measurement: the measured table alone.
#include <string>
#include <vector>

#include "trueaxis/export/compensation_table.hpp"
#include "trueaxis/export/resample.hpp"
#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::exporter {

struct HeidenhainState {
  std::string name;         // file-name part: COLD, OFF, FLOOD, ...
  std::string description;  // DOC column
  CompensationTable table;
  bool active = false;
};

// `options` as for ResampleModel. No state is active when the model has no gains for the
// requested coolant (the caller refuses that).
std::vector<HeidenhainState> HeidenhainModelStates(const model::AxisModel& axis, const ResampleOptions& options,
                                                   const std::string& source);

struct HeidenhainFile {
  std::string file_name;  // <STEM>_<STATE>.COM, or the .CMA itself (last)
  std::string text;
};
// The .COM files and, last, the .CMA `cma_file_name` (its stem, upper case, names the .COM files).
std::vector<HeidenhainFile> WriteHeidenhainSet(const std::vector<HeidenhainState>& states, const std::string& axis,
                                               const std::string& cma_file_name, ValueSign sign,
                                               const std::string& generator);

}  // namespace trueaxis::exporter
