#include "trueaxis/station/csv_cycle_log.hpp"

#include <filesystem>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/text_file.hpp"

namespace trueaxis::station {

namespace fs = std::filesystem;

CsvCycleLog::CsvCycleLog(const std::string& path, std::vector<std::string> axis_names,
                         const std::vector<std::string>& channel_names)
    : axis_names_(std::move(axis_names)) {
  std::string header = "time_s,alarms";
  for (const auto& a : axis_names_) header += "," + a + "_position_mm," + a + "_correction_um";
  for (const auto& ch : channel_names) header += ",t_" + ch + "_c";
  if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
  std::error_code ec;
  const bool existing = fs::exists(path, ec) && fs::file_size(path, ec) > 0;
  if (existing) {
    const std::string text = ReadTextFile(path);
    const std::string first = text.substr(0, text.find('\n'));
    if (first != header)
      throw InputError(path, 1, "header",
                       "the log has other columns (written by another configuration): move it away or name "
                       "another [history] csv");
    const auto last_newline = text.rfind('\n');
    if (last_newline + 1 != text.size()) {
      fs::resize_file(path, last_newline + 1);  // drop the row a kill -9 cut short
      repaired_ = true;
    }
  }
  out_.open(path, std::ios::app);
  if (!out_) throw InputError(path, 0, "history.csv", "cannot open for writing");
  if (!existing) out_ << header << "\n";
}

void CsvCycleLog::Write(const runtime::CycleRecord& r) {
  out_ << fmt::format("{:.3f},{}", r.time_s, runtime::RecordAlarmNames(r, axis_names_));
  for (std::size_t i = 0; i < r.axis_count; ++i)
    out_ << fmt::format(",{:.4f},{:.3f}", r.axes[i].cnc_position_mm, r.axes[i].output_um);
  for (std::size_t i = 0; i < r.channel_count; ++i) out_ << fmt::format(",{:.3f}", r.temp_c[i]);
  out_ << "\n";
}

}  // namespace trueaxis::station
