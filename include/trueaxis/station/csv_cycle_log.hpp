#pragma once
// CsvCycleLog: the decimated CSV log of an installation's cycles ([history] csv, docs/runtime.md):
// time, alarms, per axis position/correction, per channel value. A run appends to the log of
// earlier runs (never overwrites it); a last row cut short by a kill -9 is removed first, and a
// log with other columns is refused (InputError naming the file) rather than mixed.
#include <fstream>
#include <string>
#include <vector>

#include "trueaxis/runtime/cycle_recorder.hpp"

namespace trueaxis::station {

class CsvCycleLog {
 public:
  // Creates the file's folder when missing.
  CsvCycleLog(const std::string& path, std::vector<std::string> axis_names, const std::vector<std::string>& channel_names);
  bool repaired() const { return repaired_; }  // a row cut short was removed
  void Write(const runtime::CycleRecord& record);
  void Flush() { out_.flush(); }

 private:
  std::ofstream out_;
  std::vector<std::string> axis_names_;
  bool repaired_ = false;
};

}  // namespace trueaxis::station
