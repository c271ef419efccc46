#include "trueaxis/thermal/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::thermal {

std::vector<ChannelMetrics> ResidualMetrics(const ThermalSeries& s, const Eigen::MatrixXd& predicted,
                                            const std::vector<Eigen::Index>& rows) {
  std::vector<ChannelMetrics> out;
  for (Eigen::Index c = 0; c < s.errors_um.cols(); ++c) {
    ChannelMetrics m;
    m.channel = s.error_names[static_cast<std::size_t>(c)];
    double sq = 0;
    for (Eigen::Index r : rows) {
      const double e = s.errors_um(r, c) - (predicted.size() ? predicted(r, c) : 0.0);
      sq += e * e;
      m.max_abs_um = std::max(m.max_abs_um, std::abs(e));
      ++m.samples;
    }
    m.rmse_um = m.samples ? std::sqrt(sq / m.samples) : 0.0;
    out.push_back(m);
  }
  return out;
}

std::vector<int> ParseBlockList(const std::string& text, int count, const std::string& field) {
  std::string t(Trim(text));
  std::vector<int> out;
  if (t == "all") {
    for (int i = 0; i < count; ++i) out.push_back(i);
    return out;
  }
  std::set<int> seen;
  std::size_t pos = 0;
  while (pos <= t.size()) {
    auto comma = t.find(',', pos);
    std::string part(Trim(std::string_view(t).substr(pos, comma == std::string::npos ? std::string::npos : comma - pos)));
    pos = comma == std::string::npos ? t.size() + 1 : comma + 1;
    auto dash = part.find('-', 1);
    auto a = ParseInt(part.substr(0, dash));
    auto b = dash == std::string::npos ? a : ParseInt(part.substr(dash + 1));
    if (!a || !b || *a > *b)
      throw InputError("command line", 0, field,
                       fmt::format("'{}' is not a block index or range (e.g. 1-8,10 or all)", part));
    if (*a < 0 || *b >= count)
      throw InputError("command line", 0, field,
                       fmt::format("block {} does not exist: the series has blocks 0..{}", *a < 0 ? *a : *b, count - 1));
    for (long long i = *a; i <= *b; ++i)
      if (seen.insert(static_cast<int>(i)).second) out.push_back(static_cast<int>(i));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<Eigen::Index> RowsOfBlocks(const std::vector<SpeedBlock>& blocks, const std::vector<int>& chosen) {
  std::vector<Eigen::Index> rows;
  for (int b : chosen)
    for (Eigen::Index r = blocks[static_cast<std::size_t>(b)].first_row; r <= blocks[static_cast<std::size_t>(b)].last_row; ++r)
      rows.push_back(r);
  std::sort(rows.begin(), rows.end());
  return rows;
}

}  // namespace trueaxis::thermal
