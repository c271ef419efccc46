#include "trueaxis/campaign/test_targets.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::campaign {

bool TargetOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (!(spacing_mm >= 1 && spacing_mm <= 1000)) return fail("--spacing-mm must be 1–1000 mm");
  if (!(overrun_mm >= 0.5 && overrun_mm <= 50)) return fail("--overrun-mm must be 0.5–50 mm");
  if (!(end_clearance_mm >= 0 && end_clearance_mm <= 100)) return fail("--end-clearance-mm must be 0–100 mm");
  if (runs < 1 || runs > 20) return fail("--runs must be 1–20 (ISO 230-2: 5)");
  if (!(dwell_s >= 0.5 && dwell_s <= 60)) return fail("--dwell-s must be 0.5–60 s");
  if (!(feed_mm_min >= 10 && feed_mm_min <= 60000)) return fail("--feed-mm-min must be 10–60000 mm/min");
  return true;
}

int Iso230_2MinimumTargets(double measurement_travel_mm) {
  return std::max(5, static_cast<int>(std::ceil(5.0 * measurement_travel_mm / 1000.0 - 1e-9)));
}

namespace {

double Micrometre(double mm) { return std::round(mm * 1000.0) / 1000.0; }

// A uniform value in [−1, 1] from a splitmix64 stream: the same list on every platform for a seed.
class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : state_(seed * 0x9E3779B97F4A7C15ull + 0x7A23) {}
  double Next() {
    state_ += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return 2.0 * static_cast<double>(z >> 11) / 9007199254740992.0 - 1.0;
  }

 private:
  std::uint64_t state_;
};

}  // namespace

AxisTargets PlanAxisTargets(const CampaignAxis& axis, const TargetOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("command line", 0, "", why);
  const double margin = o.overrun_mm + o.end_clearance_mm;
  const double first = Micrometre(axis.min_mm + margin), last = Micrometre(axis.max_mm - margin);
  const int minimum = Iso230_2MinimumTargets(last - first);
  // p from the spacing asked for, but never fewer targets than ISO 230-2 asks for.
  int intervals = std::max(1, static_cast<int>(std::round((last - first) / o.spacing_mm)));
  intervals = std::max(intervals, minimum - 1);
  const double p = (last - first) / intervals;
  if (!(last > first) || p < 1)
    throw InputError("command line", 0, "--overrun-mm",
                     fmt::format("axis {} ({}–{} mm) is too short for {} targets with {} mm of overrun and {} mm of "
                                 "clearance at each end", axis.name, axis.min_mm, axis.max_mm, minimum, o.overrun_mm,
                                 o.end_clearance_mm));
  AxisTargets t;
  t.axis = axis.name;
  t.spacing_mm = p;
  t.random_max_mm = o.random_component ? std::min(axis.lead_mm / 2, p / 4) : 0;
  t.overrun_mm = o.overrun_mm;
  t.dwell_s = o.dwell_s;
  t.feed_mm_min = o.feed_mm_min;
  // Each axis its own stream: the lists of two axes with the same lead do not share their r_i.
  std::uint64_t axis_seed = o.seed;
  for (char c : axis.name) axis_seed = axis_seed * 131 + static_cast<unsigned char>(c);
  Uniform u(axis_seed);
  for (int i = 0; i <= intervals; ++i) {
    const double r = (i == 0 || i == intervals) ? 0.0 : t.random_max_mm * u.Next();
    t.targets_mm.push_back(Micrometre(first + i * p + r));
  }
  return t;
}

std::vector<std::string> TargetProblems(const CampaignAxis& axis, const AxisTargets& t) {
  std::vector<std::string> out;
  if (t.targets_mm.empty()) return {fmt::format("axis {}: no targets", axis.name)};
  const double first = t.targets_mm.front(), last = t.targets_mm.back();
  if (first - t.overrun_mm < axis.min_mm - 1e-9)
    out.push_back(fmt::format("axis {}: the overrun below the first target reaches {} mm, beyond the limit {} mm",
                              axis.name, first - t.overrun_mm, axis.min_mm));
  if (last + t.overrun_mm > axis.max_mm + 1e-9)
    out.push_back(fmt::format("axis {}: the overrun above the last target reaches {} mm, beyond the limit {} mm",
                              axis.name, last + t.overrun_mm, axis.max_mm));
  for (std::size_t i = 1; i < t.targets_mm.size(); ++i)
    if (!(t.targets_mm[i] > t.targets_mm[i - 1]))
      out.push_back(fmt::format("axis {}: targets {} and {} are not ascending", axis.name, i, i + 1));
  const int minimum = Iso230_2MinimumTargets(last - first);
  if (static_cast<int>(t.targets_mm.size()) < minimum)
    out.push_back(fmt::format("axis {}: {} targets over {} mm, ISO 230-2 asks for at least {}", axis.name,
                              t.targets_mm.size(), last - first, minimum));
  for (std::size_t i = 0; i < t.targets_mm.size(); ++i) {
    const double even = first + static_cast<double>(i) * t.spacing_mm;
    if (std::abs(t.targets_mm[i] - even) > t.random_max_mm + 0.0011)
      out.push_back(fmt::format("axis {}: target {} at {} mm is {} mm off its even place {} mm (bound {} mm)", axis.name,
                                i + 1, t.targets_mm[i], t.targets_mm[i] - even, even, t.random_max_mm));
  }
  return out;
}

double TestDurationS(const AxisTargets& t, int runs) {
  if (t.targets_mm.empty()) return 0;
  const double span = t.targets_mm.back() - t.targets_mm.front() + 2 * t.overrun_mm;
  const double per_run_s = 2 * span / t.feed_mm_min * 60 + 2 * static_cast<double>(t.targets_mm.size()) * t.dwell_s;
  return runs * per_run_s;
}

}  // namespace trueaxis::campaign
