#pragma once
// Piecewise-linear interpolation in a table of increasing abscissae, held flat
// beyond both ends — the one implementation shared by the model's Er(x) table,
// the controller-table resampling and AppliedCorrectionUm. Pure, allocation-free
// (used on the real-time path). An empty table gives 0.
#include <algorithm>
#include <cstddef>
#include <span>

namespace trueaxis {

inline double InterpolateClamped(std::span<const double> xs, std::span<const double> ys, double x) {
  if (xs.empty()) return 0;
  if (x <= xs.front()) return ys.front();
  if (x >= xs.back()) return ys.back();
  const auto it = std::upper_bound(xs.begin(), xs.end(), x);
  const std::size_t i = static_cast<std::size_t>(it - xs.begin());
  const double t = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
  return ys[i - 1] + t * (ys[i] - ys[i - 1]);
}

}  // namespace trueaxis
