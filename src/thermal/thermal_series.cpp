#include "trueaxis/thermal/thermal_series.hpp"

#include <algorithm>

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

int ThermalSeries::ExperimentOf(Eigen::Index row) const {
  if (row < 0 || static_cast<std::size_t>(row) >= experiment.size()) return 0;
  return experiment[static_cast<std::size_t>(row)];
}

int ThermalSeries::ExperimentCount() const {
  return experiment_names.empty() ? 1 : static_cast<int>(experiment_names.size());
}

ThermalSeries ConcatenateExperiments(const std::vector<ThermalSeries>& parts, std::vector<std::string>* warnings) {
  if (parts.empty()) throw InputError("experiments", "no series given");
  if (parts.size() == 1) return parts.front();
  const ThermalSeries& first = parts.front();
  // Sensors every part has, in the first part's order.
  std::vector<std::string> sensors;
  for (const auto& name : first.temperature_names) {
    bool everywhere = true;
    for (const auto& p : parts) everywhere = everywhere && p.TemperatureIndex(name).has_value();
    if (everywhere) sensors.push_back(name);
    else if (warnings)
      warnings->push_back(fmt::format("sensor '{}' is not in every experiment: dropped", name));
  }
  if (sensors.empty()) throw InputError(first.source, 0, "", "the experiments share no temperature sensor");
  ThermalSeries out;
  out.metadata = first.metadata;
  out.has_time = true;
  out.temperature_names = sensors;
  out.error_names = first.error_names;
  Eigen::Index rows = 0;
  for (const auto& p : parts) {
    if (p.error_names != first.error_names)
      throw InputError(p.source, 0, "", fmt::format("error channels ({}) differ from {}'s ({})",
                                                     fmt::join(p.error_names, ", "), first.source,
                                                     fmt::join(first.error_names, ", ")));
    if (!p.has_time) throw InputError(p.source, 0, "time_s", "an experiment needs time_s to be joined with others");
    if (p.ExperimentCount() > 1) throw InputError(p.source, 0, "", "already holds several experiments");
    for (const auto& other : parts)
      if (&other != &p && other.source == p.source)
        throw InputError(p.source, 0, "", "the same recording is given twice");
    rows += p.Rows();
    out.source += (out.source.empty() ? "" : " + ") + p.source;
    out.experiment_names.push_back(p.source);
  }
  out.has_position = true, out.has_spindle = true, out.has_coolant = true;
  for (const auto& p : parts) {
    out.has_position = out.has_position && p.has_position;
    out.has_spindle = out.has_spindle && p.has_spindle;
    out.has_coolant = out.has_coolant && p.has_coolant;
  }
  out.temperatures_c.resize(rows, static_cast<Eigen::Index>(sensors.size()));
  out.errors_um.resize(rows, static_cast<Eigen::Index>(first.error_names.size()));
  Eigen::Index at = 0;
  double offset = 0;
  for (std::size_t e = 0; e < parts.size(); ++e) {
    const ThermalSeries& p = parts[e];
    if (p.Rows() == 0) throw InputError(p.source, 0, "", "no rows");
    const double shift = e == 0 ? 0.0 : offset - p.time_s.front();
    for (Eigen::Index r = 0; r < p.Rows(); ++r, ++at) {
      const auto ru = static_cast<std::size_t>(r);
      out.time_s.push_back(p.time_s[ru] + shift);
      out.source_line.push_back(p.LineOf(r));
      out.experiment.push_back(static_cast<int>(e));
      for (std::size_t k = 0; k < sensors.size(); ++k)
        out.temperatures_c(at, static_cast<Eigen::Index>(k)) =
            p.temperatures_c(r, static_cast<Eigen::Index>(*p.TemperatureIndex(sensors[k])));
      out.errors_um.row(at) = p.errors_um.row(r);
      if (out.has_position) out.position_mm.push_back(p.position_mm[ru]);
      if (out.has_spindle) out.spindle_rpm.push_back(p.spindle_rpm[ru]);
      if (out.has_coolant) out.coolant.push_back(p.coolant[ru]);
    }
    offset = out.time_s.back() + kExperimentGapS;
  }
  return out;
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
  out.experiment_names = s.experiment_names;
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
    if (!s.experiment.empty()) out.experiment.push_back(s.experiment[ru]);
  }
  return out;
}

double MedianTimeStepS(const ThermalSeries& s) {
  if (s.time_s.size() < 2) return 0;
  std::vector<double> steps;
  for (std::size_t r = 1; r < s.time_s.size(); ++r) steps.push_back(s.time_s[r] - s.time_s[r - 1]);
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

double LongestExperimentS(const ThermalSeries& s) {
  double longest = 0;
  for (Eigen::Index r = 0, first = 0; r < s.Rows(); ++r)
    if (r + 1 == s.Rows() || s.ExperimentOf(r + 1) != s.ExperimentOf(r)) {
      longest = std::max(longest, s.time_s[static_cast<std::size_t>(r)] - s.time_s[static_cast<std::size_t>(first)]);
      first = r + 1;
    }
  return longest;
}

ThermalSeries SelectTemperatureSensors(const ThermalSeries& s, const std::vector<std::string>& names) {
  ThermalSeries out = s;
  out.temperature_names = names;
  out.temperatures_c.resize(s.Rows(), static_cast<Eigen::Index>(names.size()));
  for (std::size_t k = 0; k < names.size(); ++k) {
    auto idx = s.TemperatureIndex(names[k]);
    if (!idx)
      throw InputError(s.source, 0, names[k],
                       fmt::format("no such temperature sensor; the series has: {}", fmt::join(s.temperature_names, ", ")));
    for (std::size_t j = 0; j < k; ++j)
      if (names[j] == names[k]) throw InputError(s.source, 0, names[k], "sensor named twice");
    out.temperatures_c.col(static_cast<Eigen::Index>(k)) = s.temperatures_c.col(static_cast<Eigen::Index>(*idx));
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
    if (r == n || rpm(r) != cur.spindle_rpm || s.ExperimentOf(r) != s.ExperimentOf(r - 1)) {
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
