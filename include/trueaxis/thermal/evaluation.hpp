#pragma once
// Train/validate evaluation of thermal models on a recording split into
// speed blocks (docs/thermal-models.md "Evaluation").
//
// The residual is measured - predicted (what is left after compensation);
// the no-compensation baseline's residual is the measured error itself.
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal {

struct ChannelMetrics {
  std::string channel;
  int samples = 0;
  double rmse_um = 0;
  double max_abs_um = 0;
};

// Metrics over `rows` of measured - predicted (predicted may be empty: baseline).
std::vector<ChannelMetrics> ResidualMetrics(const ThermalSeries& series, const Eigen::MatrixXd& predicted_um,
                                            const std::vector<Eigen::Index>& rows);

// Parses a block list such as "1-8", "0,2,4-6" or "all" against `block_count`
// blocks; InputError(field) on bad text or out-of-range indices.
std::vector<int> ParseBlockList(const std::string& text, int block_count, const std::string& field);
// The rows of the given blocks, in row order.
std::vector<Eigen::Index> RowsOfBlocks(const std::vector<SpeedBlock>& blocks, const std::vector<int>& chosen);

}  // namespace trueaxis::thermal
