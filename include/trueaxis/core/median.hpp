#pragma once
// The median of a set of values: the middle one, or the mean of the two middle ones for an even
// count. The caller decides what an empty set means (this refuses it: std::invalid_argument).
#include <algorithm>
#include <stdexcept>
#include <vector>

namespace trueaxis {

inline double Median(std::vector<double> v) {
  if (v.empty()) throw std::invalid_argument("the median of no values");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

}  // namespace trueaxis
