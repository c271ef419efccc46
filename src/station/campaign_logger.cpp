#include "trueaxis/station/campaign_logger.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/coolant.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/core/text_lines.hpp"
#include "trueaxis/measure/campaign_log.hpp"
#include "trueaxis/measure/campaign_manifest.hpp"

namespace trueaxis::station {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Fixed(double v, int digits) {
  if (!std::isfinite(v)) return "";
  const double scale = std::pow(10.0, digits);
  return FormatShortest(std::round(v * scale) / scale);
}

void AppendText(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "ab");
  if (!f) throw InputError(path, 0, "", "cannot be opened for appending");
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  const bool flushed = std::fflush(f) == 0;
  std::fclose(f);
  if (!ok || !flushed) throw std::runtime_error(path + ": write failed (disk full?)");
}
}  // namespace

CampaignLogger::CampaignLogger(std::string path, std::vector<std::string> axis_names, std::vector<std::string> sensor_names)
    : path_(std::move(path)), axes_(std::move(axis_names)), sensors_(std::move(sensor_names)), last_time_s_(kNaN) {
  travel_mm_.assign(axes_.size(), 0.0);
  last_counter_mm_.assign(axes_.size(), kNaN);
  last_position_mm_.assign(axes_.size(), kNaN);
  position_mm_.assign(axes_.size(), kNaN);
  const std::string header = Header();
  if (!std::filesystem::exists(path_) || std::filesystem::file_size(path_) == 0) {
    WriteTextFile(path_, header);
    return;
  }
  // Continue the file: same columns, the last row's time and travels (read as the fit reads them).
  const std::string text = ReadTextFile(path_);
  LineCursor cursor(text);
  while (cursor.Next()) {
    const std::string_view line = cursor.line();
    if (line.empty() || line[0] == '#') continue;
    if (std::string(line) + "\n" != header)
      throw InputError(path_, cursor.number(), "",
                       fmt::format("the log's columns are not this machine's:\n  file:    {}\n  machine: {}(same axes and "
                                   "channels in the same order, or start another campaign folder)",
                                   line, header));
    break;
  }
  if (!text.empty() && text.back() != '\n')
    throw InputError(path_, 0, "", "the last row is cut short (no line end): remove it before logging on");
  if (text.find('\n', text.find(header) + header.size()) == std::string::npos) return;  // header only
  const measure::TemperatureLog log = measure::ReadTemperatureLog(path_);
  resumed_rows_ = log.time_s.size();
  last_time_s_ = log.time_s.back();
  for (std::size_t a = 0; a < axes_.size(); ++a) {
    const auto it = log.travel_mm.find(LowerAscii(axes_[a]));
    if (it == log.travel_mm.end()) continue;
    for (auto v = it->second.rbegin(); v != it->second.rend(); ++v)
      if (std::isfinite(*v)) {
        travel_mm_[a] = *v;
        break;
      }
  }
  if (!log.coolant.empty()) coolant_ = CoolantStateName(log.coolant.back());
}

std::string CampaignLogger::Header() const { return measure::CampaignLogHeader(axes_, sensors_); }

void CampaignLogger::Poll(std::span<const hw::AxisState> axes) {
  for (std::size_t a = 0; a < axes_.size() && a < axes.size(); ++a) {
    const auto& s = axes[a];
    if (std::isfinite(s.travel_mm)) {
      if (std::isfinite(last_counter_mm_[a])) {
        const double inc = s.travel_mm - last_counter_mm_[a];
        travel_mm_[a] += inc >= 0 ? inc : s.travel_mm;  // went back: the counter restarted from 0
      }
      last_counter_mm_[a] = s.travel_mm;
    } else if (std::isfinite(last_position_mm_[a])) {
      travel_mm_[a] += std::abs(s.position_mm - last_position_mm_[a]);
    }
    last_position_mm_[a] = s.position_mm;
    position_mm_[a] = s.position_mm;
  }
}

bool CampaignLogger::Append(double time_s, const std::string& date, const std::optional<hw::CncState>& cnc,
                            std::optional<std::span<const hw::RawTemperature>> temperatures) {
  const double t = std::round(time_s * 10) / 10;
  if (std::isfinite(last_time_s_) && !(t > last_time_s_)) return false;
  if (cnc) coolant_ = CoolantStateName(cnc->coolant);
  std::string row = Fixed(t, 1) + "," + date + "," + coolant_;
  for (double p : position_mm_) row += "," + Fixed(p, 3);
  for (double v : travel_mm_) row += "," + Fixed(v, 1);
  for (std::size_t c = 0; c < sensors_.size(); ++c) {
    std::string cell;
    if (temperatures && c < temperatures->size()) {
      const auto& r = (*temperatures)[c];
      if (!r.hardware_fault && std::isfinite(r.temp_c)) cell = Fixed(r.temp_c, 4);
    }
    row += "," + cell;
  }
  AppendText(path_, row + "\n");
  last_time_s_ = t;
  ++appended_rows_;
  return true;
}

}  // namespace trueaxis::station
