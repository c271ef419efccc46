#include "trueaxis/measure/measurement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "trueaxis/core/ascii_case.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::measure {
namespace {
constexpr double kSameTargetTolMm = 1e-6;
}

std::optional<std::string> Measurement::Meta(const std::string& key) const {
  for (const auto& [k, v] : metadata)
    if (k == key) return v;
  return std::nullopt;
}

std::optional<bool> CompensationActive(const Measurement& m) {
  const auto v = m.Meta("compensation");
  if (!v) return std::nullopt;
  const std::string s = LowerAscii(Trim(*v));
  if (s == "on" || s == "yes" || s == "true") return true;
  if (s == "off" || s == "no" || s == "false" || s == "none") return false;
  throw InputError(m.source, m.MetaLine("compensation"), "compensation",
                   fmt::format("'{}' is not a compensation state (expected on or off)", *v));
}

int Measurement::MetaLine(const std::string& key) const {
  if (!Meta(key)) return 0;
  const auto it = metadata_lines.find(key);
  return it == metadata_lines.end() ? 0 : it->second;
}

std::optional<std::string> DeviationUnitWarning(const Measurement& m) {
  constexpr double kTruestUm = 0.2, kMinSpanMm = 50;  // a real run over 50 mm: laser noise alone exceeds 0.2 µm
  if (m.points.empty()) return std::nullopt;
  double largest_um = 0, lo_mm = m.points.front().target_mm, hi_mm = lo_mm;
  for (const auto& p : m.points) {
    if (std::isfinite(p.deviation_um)) largest_um = std::max(largest_um, std::abs(p.deviation_um));
    lo_mm = std::min(lo_mm, p.target_mm);
    hi_mm = std::max(hi_mm, p.target_mm);
  }
  if (largest_um >= kTruestUm || hi_mm - lo_mm < kMinSpanMm) return std::nullopt;
  return fmt::format("every deviation is under {} µm (largest {:g} µm) over {:g} mm of travel: no axis is that "
                     "true; are the deviations in mm rather than µm?",
                     kTruestUm, largest_um, hi_mm - lo_mm);
}

void Measurement::SetMeta(const std::string& key, const std::string& value, int line) {
  if (line > 0) metadata_lines[key] = line;
  else metadata_lines.erase(key);
  for (auto& [k, v] : metadata)
    if (k == key) {
      v = value;
      return;
    }
  metadata.emplace_back(key, value);
}

std::optional<std::size_t> Measurement::SensorIndex(const std::string& name) const {
  for (std::size_t i = 0; i < sensor_names.size(); ++i)
    if (sensor_names[i] == name) return i;
  return std::nullopt;
}

std::vector<double> Measurement::Targets() const {
  std::vector<double> t;
  t.reserve(points.size());
  for (const auto& p : points) t.push_back(p.target_mm);
  std::sort(t.begin(), t.end());
  std::vector<double> out;
  for (double v : t)
    if (out.empty() || v - out.back() > kSameTargetTolMm) out.push_back(v);
  return out;
}

std::vector<int> Measurement::Runs() const {
  std::set<int> runs;
  for (const auto& p : points) runs.insert(p.run);
  return {runs.begin(), runs.end()};
}

void ValidateForEvaluation(const Measurement& m) {
  if (m.points.empty()) throw InputError(m.source, "no measurement points (empty file?)");
  const auto targets = m.Targets();
  auto target_index = [&](double t) {
    auto it = std::lower_bound(targets.begin(), targets.end(), t - kSameTargetTolMm);
    return static_cast<std::size_t>(it - targets.begin());
  };
  std::map<std::tuple<int, int, std::size_t>, int> seen;  // (run, dir, target) -> line
  std::vector<std::array<int, 2>> first_line(targets.size(), {0, 0});
  std::vector<std::array<bool, 2>> has_dir(targets.size(), {false, false});
  for (const auto& p : m.points) {
    const auto ti = target_index(p.target_mm);
    const int di = static_cast<int>(DirectionIndex(p.direction));
    auto key = std::make_tuple(p.run, di, ti);
    if (auto it = seen.find(key); it != seen.end()) {
      throw InputError(m.source, p.source_line, "target_mm",
                       fmt::format("duplicate point: run {} direction {} target {} mm already given on line {}",
                                   p.run, DirectionSymbol(p.direction), p.target_mm, it->second));
    }
    seen.emplace(key, p.source_line);
    has_dir[ti][di] = true;
    if (first_line[ti][di] == 0) first_line[ti][di] = p.source_line;
  }
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (has_dir[i][0] != has_dir[i][1]) {
      const int di = has_dir[i][0] ? 0 : 1;
      throw InputError(m.source, first_line[i][di], "direction",
                       fmt::format("target {} mm is measured only in the '{}' direction; ISO 230-2 needs both",
                                   targets[i], di == 0 ? '+' : '-'));
    }
  }
  const auto runs = m.Runs();
  if (runs.size() < 2)
    throw InputError(m.source, m.points.front().source_line, "run",
                     fmt::format("only {} run(s); repeatability needs at least 2 runs per direction", runs.size()));
}

}  // namespace trueaxis::measure
