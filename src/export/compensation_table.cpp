#include "trueaxis/export/compensation_table.hpp"

#include "trueaxis/core/interpolation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::exporter {

double CompensationTable::UniformSpacingMm() const {
  if (position_mm.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const double step = position_mm[1] - position_mm[0];
  for (std::size_t i = 1; i < position_mm.size(); ++i) {
    const double expected = position_mm[0] + step * static_cast<double>(i);
    if (std::abs(position_mm[i] - expected) > 1e-9 * std::max(1.0, std::abs(expected)) + 1e-9)
      return std::numeric_limits<double>::quiet_NaN();
  }
  return step;
}


double AppliedCorrectionUm(const CompensationTable& table, double position_mm, Direction direction) {
  const auto& column = direction == Direction::kForward ? table.forward_um : table.reverse_um;
  double c = InterpolateClamped(table.position_mm, column, position_mm);
  if (!table.bidirectional) c += DirectionSign(direction) * 0.5 * table.backlash_um;
  // Thermal line kept out of the table: correction = −error.
  c -= table.thermal_tan_beta_um_per_mm * (table.thermal_reference_mm - position_mm);
  return c;
}

void ValidateTable(const CompensationTable& table, const std::string& source) {
  const std::size_t n = table.position_mm.size();
  if (n == 0) throw InputError(source, 0, "position_mm", "the table has no points");
  if (table.forward_um.size() != n || table.reverse_um.size() != n)
    throw InputError(source, 0, "forward_um",
                     fmt::format("column sizes differ: {} positions, {} forward, {} reverse values", n,
                                 table.forward_um.size(), table.reverse_um.size()));
  for (std::size_t i = 0; i < n; ++i) {
    // A value no controller table holds (1e308, a lost unit) is refused, not written: a writer
    // would print it as ±inf or a 300-digit number into the controller's file.
    if (auto why = ImplausiblePositionMm(table.position_mm[i]))
      throw InputError(source, 0, fmt::format("position_mm[{}]", i), *why);
    if (auto why = ImplausibleDeviationUm(table.forward_um[i]))
      throw InputError(source, 0, fmt::format("forward_um[{}]", i), fmt::format("correction at {} mm: {}", table.position_mm[i], *why));
    if (auto why = ImplausibleDeviationUm(table.reverse_um[i]))
      throw InputError(source, 0, fmt::format("reverse_um[{}]", i), fmt::format("correction at {} mm: {}", table.position_mm[i], *why));
    if (i > 0 && !(table.position_mm[i] > table.position_mm[i - 1]))
      throw InputError(source, 0, fmt::format("position_mm[{}]", i),
                       fmt::format("positions must be strictly ascending ({} mm follows {} mm)",
                                   table.position_mm[i], table.position_mm[i - 1]));
  }
  if (auto why = ImplausibleDeviationUm(table.backlash_um)) throw InputError(source, 0, "backlash_um", *why);
  if (!std::isfinite(table.thermal_tan_beta_um_per_mm))
    throw InputError(source, 0, "thermal_tan_beta_um_per_mm", "is not a finite number");
  if (auto why = ImplausiblePositionMm(table.thermal_reference_mm))
    throw InputError(source, 0, "thermal_reference_mm", *why);
}

void ValidateReadTable(const CompensationTable& table, const std::string& source, const std::vector<int>& point_lines) {
  const auto line_of = [&](std::size_t i) { return i < point_lines.size() ? point_lines[i] : 0; };
  // The implausible values first, each at its line (ValidateTable below names only the index).
  const std::size_t n = std::min({table.position_mm.size(), table.forward_um.size(), table.reverse_um.size()});
  for (std::size_t i = 0; i < n; ++i) {
    if (auto why = ImplausiblePositionMm(table.position_mm[i]))
      throw InputError(source, line_of(i), "position_mm", *why);
    for (const auto* column : {&table.forward_um, &table.reverse_um})
      if (auto why = ImplausibleDeviationUm((*column)[i]))
        throw InputError(source, line_of(i), column == &table.forward_um ? "forward_um" : "reverse_um",
                         fmt::format("correction at {} mm: {}", table.position_mm[i], *why));
  }
  ValidateTable(table, source);
  if (table.size() < 2)
    throw InputError(source, line_of(0), "position_mm",
                     "the table has a single point; a compensation table needs at least 2 (as every writer does)");
}

}  // namespace trueaxis::exporter
