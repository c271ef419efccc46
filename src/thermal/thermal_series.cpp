#include "trueaxis/thermal/thermal_series.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::thermal {

std::optional<std::size_t> ThermalSeries::TemperatureIndex(const std::string& name) const {
  for (std::size_t i = 0; i < temperature_names.size(); ++i)
    if (temperature_names[i] == name) return i;
  return std::nullopt;
}

std::optional<std::size_t> ThermalSeries::ErrorIndex(const std::string& name) const {
  for (std::size_t i = 0; i < error_names.size(); ++i)
    if (error_names[i] == name) return i;
  return std::nullopt;
}

int ThermalSeries::LineOf(Eigen::Index row) const {
  if (row < 0 || static_cast<std::size_t>(row) >= source_line.size()) return 0;
  return source_line[static_cast<std::size_t>(row)];
}

ThermalSeries SelectRows(const ThermalSeries& s, const std::vector<Eigen::Index>& rows) {
  ThermalSeries out;
  out.source = s.source;
  out.metadata = s.metadata;
  out.has_time = s.has_time;
  out.temperature_names = s.temperature_names;
  out.error_names = s.error_names;
  out.has_position = s.has_position;
  out.has_spindle = s.has_spindle;
  out.has_coolant = s.has_coolant;
  const auto n = static_cast<Eigen::Index>(rows.size());
  out.temperatures_c.resize(n, s.temperatures_c.cols());
  out.errors_um.resize(n, s.errors_um.cols());
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index r = rows[static_cast<std::size_t>(k)];
    const auto ru = static_cast<std::size_t>(r);
    out.time_s.push_back(s.time_s[ru]);
    out.source_line.push_back(s.LineOf(r));
    out.temperatures_c.row(k) = s.temperatures_c.row(r);
    out.errors_um.row(k) = s.errors_um.row(r);
    if (s.has_position) out.position_mm.push_back(s.position_mm[ru]);
    if (s.has_spindle) out.spindle_rpm.push_back(s.spindle_rpm[ru]);
    if (s.has_coolant) out.coolant.push_back(s.coolant[ru]);
  }
  return out;
}

ThermalSeries SelectErrorChannels(const ThermalSeries& s, const std::vector<std::string>& names) {
  ThermalSeries out = s;
  out.error_names = names;
  out.errors_um.resize(s.Rows(), static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    auto idx = s.ErrorIndex(names[k]);
    if (!idx) {
      std::string have;
      for (const auto& e : s.error_names) have += (have.empty() ? "" : ", ") + e;
      throw InputError(s.source, 0, names[k], fmt::format("no such error channel; the series has: {}", have));
    }
    out.errors_um.col(static_cast<Eigen::Index>(k)) = s.errors_um.col(static_cast<Eigen::Index>(*idx));
  }
  return out;
}

std::vector<SpeedBlock> SpeedBlocks(const ThermalSeries& s) {
  std::vector<SpeedBlock> blocks;
  const Eigen::Index n = s.Rows();
  if (n == 0) return blocks;
  auto rpm = [&](Eigen::Index r) { return s.has_spindle ? s.spindle_rpm[static_cast<std::size_t>(r)] : 0.0; };
  SpeedBlock cur;
  cur.spindle_rpm = rpm(0);
  cur.start_s = s.time_s[0];
  for (Eigen::Index r = 1; r <= n; ++r) {
    if (r == n || rpm(r) != cur.spindle_rpm) {
      cur.last_row = r - 1;
      cur.end_s = s.time_s[static_cast<std::size_t>(r - 1)];
      blocks.push_back(cur);
      if (r == n) break;
      cur = SpeedBlock{};
      cur.index = static_cast<int>(blocks.size());
      cur.spindle_rpm = rpm(r);
      cur.first_row = r;
      cur.start_s = s.time_s[static_cast<std::size_t>(r)];
    }
  }
  return blocks;
}

}  // namespace trueaxis::thermal
