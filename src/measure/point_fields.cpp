#include "point_fields.hpp"

#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"
#include "trueaxis/core/plausibility.hpp"

namespace trueaxis::measure::detail {

int ReadRunField(std::string_view f, const std::string& source, int line, const std::string& field) {
  auto v = ParseInt(f);
  if (!v || *v < 1 || *v > 100000)
    throw InputError(source, line, field, fmt::format("'{}' is not a run number (integer >= 1)", f));
  return static_cast<int>(*v);
}

double ReadQuantityField(std::string_view f, Quantity q, const std::string& source, int line, const std::string& field,
                         double scale) {
  auto v = ParseDouble(f);
  if (!v || !std::isfinite(*v)) throw InputError(source, line, field, fmt::format("'{}' is not a finite number", f));
  const double value = *v * scale;
  const auto implausible = q == Quantity::kTargetMm      ? ImplausiblePositionMm(value)
                           : q == Quantity::kDeviationUm ? ImplausibleDeviationUm(value)
                                                         : ImplausibleTimeS(value);
  if (implausible) throw InputError(source, line, field, *implausible);
  return value;
}

std::optional<double> ReadTemperatureField(std::string_view f, const std::string& source, int line,
                                           const std::string& field) {
  if (f.empty()) return std::nullopt;
  auto v = ParseDouble(f);
  if (!v || !std::isfinite(*v))
    throw InputError(source, line, field, fmt::format("'{}' is not a temperature in °C (empty means not read)", f));
  if (auto why = ImplausibleTemperatureC(*v)) throw InputError(source, line, field, *why);
  return *v;
}

}  // namespace trueaxis::measure::detail
