#include "trueaxis/thermal/time_folds.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace trueaxis::thermal {

std::string TimeFolds::Name() const {
  return fmt::format("{} {}-fold", by_experiment ? "leave-one-experiment-out" : "forward-chaining", folds.size());
}

TimeFolds MakeTimeFolds(const ThermalSeries& s) {
  TimeFolds out;
  const Eigen::Index n = s.Rows();
  std::vector<int> ids;
  if (!s.experiment.empty())
    for (Eigen::Index r = 0; r < n; ++r) {
      const int e = s.experiment[static_cast<std::size_t>(r)];
      if (std::find(ids.begin(), ids.end(), e) == ids.end()) ids.push_back(e);
    }
  if (ids.size() > 1) {
    out.by_experiment = true;
    for (int e : ids) {
      TimeFold f;
      for (Eigen::Index r = 0; r < n; ++r)
        (s.experiment[static_cast<std::size_t>(r)] == e ? f.validate_rows : f.train_rows).push_back(r);
      if (f.train_rows.size() >= 3 && !f.validate_rows.empty()) out.folds.push_back(std::move(f));
    }
    return out;
  }
  const Eigen::Index first = n / 2;
  for (int k = 0; k < kForwardFolds; ++k) {
    const Eigen::Index lo = first + (n - first) * k / kForwardFolds;
    const Eigen::Index hi = first + (n - first) * (k + 1) / kForwardFolds;
    if (lo < 3 || hi <= lo) continue;
    TimeFold f;
    for (Eigen::Index r = 0; r < lo; ++r) f.train_rows.push_back(r);
    for (Eigen::Index r = lo; r < hi; ++r) f.validate_rows.push_back(r);
    out.folds.push_back(std::move(f));
  }
  return out;
}

std::vector<std::vector<Eigen::Index>> UseLikeBlocks(const TimeFolds& folds) {
  std::vector<std::vector<Eigen::Index>> out;
  if (folds.folds.empty()) return out;
  if (folds.by_experiment) {
    for (const TimeFold& f : folds.folds) out.push_back(f.validate_rows);
    return out;
  }
  const std::vector<Eigen::Index>& last = folds.folds.back().validate_rows;
  const std::size_t n = last.size();
  for (std::size_t k = 0; k < static_cast<std::size_t>(kForwardFolds); ++k) {
    std::vector<Eigen::Index> block(last.begin() + static_cast<std::ptrdiff_t>(n * k / kForwardFolds),
                                    last.begin() + static_cast<std::ptrdiff_t>(n * (k + 1) / kForwardFolds));
    if (!block.empty()) out.push_back(std::move(block));
  }
  return out;
}

}  // namespace trueaxis::thermal
