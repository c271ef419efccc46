#include "trueaxis/thermal/series_cleaning.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/number_text.hpp"

namespace trueaxis::thermal {
namespace {

struct GapScan {
  Eigen::Index missing = 0;
  Eigen::Index leading = 0;   // NaNs before the first reading
  Eigen::Index trailing = 0;  // NaNs after the last reading
  Eigen::Index longest_interior = 0;
  Eigen::Index longest_interior_start = -1;
};

GapScan Scan(const Eigen::Ref<const Eigen::VectorXd>& v) {
  GapScan g;
  const Eigen::Index n = v.size();
  Eigen::Index first = 0;
  while (first < n && std::isnan(v(first))) ++first;
  g.leading = first;
  Eigen::Index last = n - 1;
  while (last >= 0 && std::isnan(v(last))) --last;
  g.trailing = n - 1 - last;
  for (Eigen::Index r = first; r <= last;) {
    if (!std::isnan(v(r))) {
      ++r;
      continue;
    }
    Eigen::Index start = r;
    while (r <= last && std::isnan(v(r))) ++r;
    if (r - start > g.longest_interior) {
      g.longest_interior = r - start;
      g.longest_interior_start = start;
    }
  }
  for (Eigen::Index r = 0; r < n; ++r) g.missing += std::isnan(v(r)) ? 1 : 0;
  return g;
}

// Fills the interior NaN runs of `v`; returns how many values, and the first filled row in *first.
int FillInterior(Eigen::Ref<Eigen::VectorXd> v, const std::vector<double>& t, Eigen::Index* first = nullptr) {
  int filled = 0;
  const Eigen::Index n = v.size();
  Eigen::Index r = 0;
  while (r < n) {
    if (!std::isnan(v(r))) {
      ++r;
      continue;
    }
    Eigen::Index start = r;
    while (r < n && std::isnan(v(r))) ++r;
    if (start == 0 || r == n) continue;  // edges are never filled (callers refused them)
    const double t0 = t[static_cast<std::size_t>(start - 1)], t1 = t[static_cast<std::size_t>(r)];
    const double v0 = v(start - 1), v1 = v(r);
    if (first && filled == 0) *first = start;
    for (Eigen::Index k = start; k < r; ++k) {
      v(k) = v0 + (v1 - v0) * (t[static_cast<std::size_t>(k)] - t0) / (t1 - t0);
      ++filled;
    }
  }
  return filled;
}

// Fills one column's short gaps and says so, per column (how many, from which line).
void FillAndReport(Eigen::Ref<Eigen::VectorXd> v, const ThermalSeries& in, const std::string& what,
                   SeriesCleaningReport* rep) {
  Eigen::Index first = 0;
  const int filled = FillInterior(v, in.time_s, &first);
  if (filled == 0) return;
  rep->interpolated_values += filled;
  rep->warnings.push_back(fmt::format("{}: {} missing value(s) filled by linear interpolation in time (the first at "
                                      "line {})", what, filled, in.LineOf(first)));
}

}  // namespace

bool SeriesCleaningOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* m) {
    if (why) *why = m;
    return false;
  };
  if (max_interpolated_gap_samples < 0) return fail("max_interpolated_gap_samples must be >= 0");
  if (!(min_temperature_std_c >= 0)) return fail("min_temperature_std_c must be >= 0");
  if (!(max_time_step_factor > 1)) return fail("max_time_step_factor must be > 1");
  return true;
}

std::string SeriesCleaningReport::BriefReport() const {
  std::string out = fmt::format("cleaning: {} value(s) interpolated, {} temperature channel(s) dropped",
                                interpolated_values, dropped_temperatures.size());
  for (const auto& w : warnings) out += "\n  warning: " + w;
  return out;
}

ThermalSeries CleanSeries(const ThermalSeries& in, const SeriesCleaningOptions& options,
                          SeriesCleaningReport* report) {
  std::string why;
  if (!options.IsValid(&why)) throw InputError("cleaning options", why);
  SeriesCleaningReport local;
  SeriesCleaningReport& rep = report ? *report : local;
  rep = SeriesCleaningReport{};
  const Eigen::Index n = in.Rows();
  if (n < 2) throw InputError(in.source, 0, "", fmt::format("{} row(s); a thermal series needs at least 2", n));
  if (options.check_error_channels && in.error_names.empty())
    throw InputError(in.source, 0, "", "no error column (e_<channel>_um or <channel>_um): nothing to model");

  // 1. Time gaps.
  if (in.has_time && n >= 3) {
    std::vector<double> steps;
    for (std::size_t i = 1; i < in.time_s.size(); ++i) steps.push_back(in.time_s[i] - in.time_s[i - 1]);
    const double median = MedianTimeStepS(in);
    for (std::size_t i = 0; i < steps.size(); ++i) {
      if (steps[i] > options.max_time_step_factor * median) {
        std::string msg = fmt::format("time jumps by {} s after {} s (median step {} s): a gap in the recording",
                                      FormatShortest(steps[i]), FormatShortest(in.time_s[i]), FormatShortest(median));
        if (!options.allow_time_gaps)
          throw InputError(in.source, in.LineOf(static_cast<Eigen::Index>(i + 1)), "time_s",
                           msg + "; split the file at the gap or pass --allow-time-gaps");
        rep.warnings.push_back(msg);
      }
    }
  }

  // 2./3. Temperature channels.
  std::vector<Eigen::Index> keep, constant;
  std::vector<std::string> constant_warnings;
  for (std::size_t c = 0; c < in.temperature_names.size(); ++c) {
    const auto col = static_cast<Eigen::Index>(c);
    const std::string field = in.temperature_names[c];
    GapScan g = Scan(in.temperatures_c.col(col));
    std::string problem;
    if (g.missing == n) {
      problem = "has no reading at all";
    } else if (g.trailing > 0) {
      problem = fmt::format("stops reading at line {} (t = {} s) and never recovers ({} of {} rows missing): "
                            "the sensor died",
                            in.LineOf(n - g.trailing), FormatShortest(in.time_s[static_cast<std::size_t>(n - g.trailing)]),
                            g.missing, n);
    } else if (g.leading > 0) {
      problem = fmt::format("has no reading before line {} ({} rows)", in.LineOf(g.leading), g.leading);
    } else if (g.longest_interior > options.max_interpolated_gap_samples) {
      problem = fmt::format("has a gap of {} rows from line {}, more than the {} that are interpolated",
                            g.longest_interior, in.LineOf(g.longest_interior_start),
                            options.max_interpolated_gap_samples);
    }
    if (!problem.empty()) {
      if (!options.drop_bad_temperature_channels)
        throw InputError(in.source, g.trailing > 0 ? in.LineOf(n - g.trailing) : 0, field,
                         "temperature " + problem);
      rep.warnings.push_back(fmt::format("temperature '{}' dropped: it {}", field, problem));
      rep.dropped_temperatures.push_back(field);
      continue;
    }
    Eigen::VectorXd v = in.temperatures_c.col(col);
    std::vector<double> finite;
    for (Eigen::Index r = 0; r < n; ++r)
      if (!std::isnan(v(r))) finite.push_back(v(r));
    double mean = 0;
    for (double x : finite) mean += x;
    mean /= static_cast<double>(finite.size());
    double var = 0;
    for (double x : finite) var += (x - mean) * (x - mean);
    const double sd = std::sqrt(var / static_cast<double>(finite.size()));
    if (sd < options.min_temperature_std_c) {
      constant.push_back(col);
      constant_warnings.push_back(fmt::format("temperature '{}' dropped: constant ({} °C, std {} °C < {} °C)", field,
                                              FormatShortest(mean), FormatShortest(sd),
                                              FormatShortest(options.min_temperature_std_c)));
      continue;
    }
    keep.push_back(col);
  }
  if (keep.empty() && !constant.empty()) {
    // A table taken at one temperature (seed 003's Z axis at 27.6 °C): every
    // sensor is constant. Keep them; models see a constant input.
    keep = constant;
    rep.warnings.push_back("every temperature is constant: kept as constant inputs (the models cannot learn a "
                           "temperature dependence from this series)");
  } else {
    for (std::size_t k = 0; k < constant.size(); ++k) {
      rep.warnings.push_back(constant_warnings[k]);
      rep.dropped_temperatures.push_back(in.temperature_names[static_cast<std::size_t>(constant[k])]);
    }
  }
  if (keep.empty())
    throw InputError(in.source, 0, "", "no usable temperature channel left after cleaning: " +
                                           (rep.warnings.empty() ? std::string("none given") : rep.warnings.back()));

  ThermalSeries out = in;
  out.temperature_names.clear();
  out.temperatures_c.resize(n, static_cast<Eigen::Index>(keep.size()));
  for (std::size_t k = 0; k < keep.size(); ++k) {
    out.temperature_names.push_back(in.temperature_names[static_cast<std::size_t>(keep[k])]);
    out.temperatures_c.col(static_cast<Eigen::Index>(k)) = in.temperatures_c.col(keep[k]);
    FillAndReport(out.temperatures_c.col(static_cast<Eigen::Index>(k)), in,
                  fmt::format("temperature '{}'", out.temperature_names.back()), &rep);
  }

  // 4./5. Error channels.
  for (std::size_t c = 0; options.check_error_channels && c < in.error_names.size(); ++c) {
    const auto col = static_cast<Eigen::Index>(c);
    const std::string field = in.error_names[c];
    GapScan g = Scan(in.errors_um.col(col));
    if (g.missing == n) throw InputError(in.source, 0, field, "error channel has no value at all");
    if (g.leading > 0)
      throw InputError(in.source, in.LineOf(0), field,
                       fmt::format("error channel has no value in the first {} row(s); cut the series so it "
                                   "starts with a measured error",
                                   g.leading));
    if (g.trailing > 0)
      throw InputError(in.source, in.LineOf(n - g.trailing), field,
                       fmt::format("error channel stops at this line ({} row(s) to the end missing); cut the series "
                                   "where the measurement ends",
                                   g.trailing));
    if (g.longest_interior > options.max_interpolated_gap_samples)
      throw InputError(in.source, in.LineOf(g.longest_interior_start), field,
                       fmt::format("error channel has a gap of {} rows, more than the {} that are interpolated; "
                                   "an error target is never invented",
                                   g.longest_interior, options.max_interpolated_gap_samples));
    FillAndReport(out.errors_um.col(col), in, fmt::format("error channel '{}'", field), &rep);
    const double range = out.errors_um.col(col).maxCoeff() - out.errors_um.col(col).minCoeff();
    if (range < 1e-9)
      rep.warnings.push_back(fmt::format("error channel '{}' is constant: there is nothing to compensate", field));
  }
  return out;
}

}  // namespace trueaxis::thermal
