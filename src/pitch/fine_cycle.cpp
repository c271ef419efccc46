#include "trueaxis/pitch/fine_cycle.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/number_text.hpp"

namespace trueaxis::pitch {

namespace {

std::uint64_t Mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9E3779B97F4A7C15ull * (b + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

double Overrun(const sim::AxisDescription& a, const FineCycleOptions& o) {
  return std::isnan(o.overrun_mm) ? std::min(5.0, a.lead_mm) : o.overrun_mm;
}

}  // namespace

bool FineCycleOptions::IsValid(std::string* why) const {
  auto fail = [why](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (per_lead < 1 || per_lead > 64) return fail("per_lead: must be 1–64");
  if (runs < 2 || runs > 20) return fail("runs: must be 2–20 (ISO 230-2 needs 2 per direction; 5 recommended)");
  if (!(feed_mm_min > 0)) return fail("feed_mm_min: must be positive");
  if (!(dwell_s >= 0)) return fail("dwell_s: must be >= 0");
  if (!std::isnan(overrun_mm) && !(overrun_mm >= 0)) return fail("overrun_mm: must be >= 0");
  if (!(end_margin_mm > 0 && end_margin_mm <= model::kMeasuredRangeToleranceMm))
    return fail("end_margin_mm: must be > 0 and at most the measured range's tolerance (0.5 mm)");
  return true;
}

std::vector<double> FineTargets(const sim::AxisDescription& a, const FineCycleOptions& o) {
  const double step = a.lead_mm / o.per_lead;
  const double lo = o.end_margin_mm, hi = a.travel_mm - o.end_margin_mm;
  if (!(hi - lo >= step))
    throw std::invalid_argument(fmt::format("axis {}: travel {} mm is shorter than one fine step ({} mm) and the end "
                                            "margins",
                                            a.name, a.travel_mm, FormatShortest(step)));
  std::vector<double> t = {lo};
  const long long k0 = static_cast<long long>(std::ceil((lo - a.reference_mm) / step - 1e-9));
  for (long long k = k0;; ++k) {
    const double x = std::round((a.reference_mm + static_cast<double>(k) * step) * 1e6) / 1e6;
    if (x > hi + 1e-9) break;
    if (x > t.back() + 1e-3) t.push_back(x);
  }
  if (t.back() < hi - 1e-3) t.push_back(hi);  // the travel's far end
  return t;
}

measure::Measurement RunFineCycle(sim::VirtualMachine& vm, std::size_t axis, sim::LaserInterferometer& laser,
                                  sim::CncInterpolator& ipo, const FineCycleOptions& o,
                                  const std::vector<std::pair<std::string, std::string>>& extra_metadata) {
  std::string why;
  if (!o.IsValid(&why)) throw std::invalid_argument("fine cycle: " + why);
  const auto& ad = vm.description().axes.at(axis);
  const auto targets = FineTargets(ad, o);
  const double over = Overrun(ad, o);
  measure::Measurement m = laser.StartMeasurement(vm);
  m.SetMeta("cycle", fmt::format("fine: every lead/{} ({} mm)", o.per_lead, FormatShortest(ad.lead_mm / o.per_lead)));
  m.SetMeta("runs", std::to_string(o.runs));
  m.SetMeta("feed_mm_min", FormatShortest(o.feed_mm_min));
  m.SetMeta("dwell_s", FormatShortest(o.dwell_s));
  m.SetMeta("overrun_mm", FormatShortest(over));
  m.SetMeta("measured_range_mm", fmt::format("{}…{} (travel 0…{}, ends reached after a {} mm reversal)",
                                             FormatShortest(targets.front()), FormatShortest(targets.back()),
                                             FormatShortest(ad.travel_mm), FormatShortest(o.end_margin_mm)));
  m.SetMeta("interpolator", fmt::format("cycle {} ms, feed-forward {}", FormatShortest(ipo.options().cycle_s * 1000),
                                        sim::FeedForwardName(ipo.options().mode)));
  m.SetMeta("ambient_start_c", fmt::format("{:.3f}", vm.AmbientC()));
  for (const auto& [k, v] : extra_metadata) m.SetMeta(k, v);

  const double t0 = vm.TimeS();
  auto record = [&](int run, Direction dir, double target) {
    ipo.MoveTo(target, o.feed_mm_min);
    ipo.Dwell(o.dwell_s);
    m.points.push_back(laser.Reading(vm, run, dir, target, t0));
  };
  // The reversals overrun where the travel allows; at its ends they reverse there (end_margin_mm before the end target).
  const auto reverse_at = [&](double x) { ipo.MoveTo(std::clamp(x, 0.0, ad.travel_mm), o.feed_mm_min); };
  sim::RunBidirectionalCycle(targets, o.runs, over, reverse_at, record);
  m.SetMeta("duration_s", FormatShortest(std::round((vm.TimeS() - t0) * 10.0) / 10.0));
  return m;
}

FineSessionResult RunFineSession(const sim::MachineDescription& machine, std::size_t axis, const FineSessionOptions& o) {
  if (o.day < 0 || o.day > 3650) throw std::invalid_argument("fine session: day must be 0–3650");
  if (axis >= machine.axes.size()) throw std::invalid_argument("fine session: no such axis");
  FineSessionResult r;
  sim::VirtualMachine vm(machine, o.seed);
  std::mt19937_64 homing_rng(Mix(o.seed, 0x40));
  r.calibration_homing = sim::HomeAxis(vm, axis, o.homing, homing_rng);
  r.homing = r.calibration_homing;
  sim::LaserInterferometer laser(sim::LaserOptions{}, Mix(o.seed, 0x1000 + static_cast<std::uint64_t>(o.day)));
  laser.Setup(vm, axis, machine.axes[axis].reference_mm);
  if (o.day > 0) {
    vm.IdleUntil(o.day * 86400.0);
    std::mt19937_64 rehome_rng(Mix(o.seed, 0x40 + static_cast<std::uint64_t>(o.day)));
    r.homing = sim::HomeAxis(vm, axis, o.homing, rehome_rng);
  } else if (o.table) {
    // Day 0 with a table: the verification follows the calibration on the same
    // day. The calibration cycle is replayed (deterministic, its readings are not
    // kept), then the axis is re-homed — so only the table and re-homing differ.
    sim::InterpolatorOptions plain_options = o.interpolator;
    plain_options.mode = sim::FeedForward::kOff;
    sim::CncInterpolator plain(vm, axis, plain_options, {});
    RunFineCycle(vm, axis, laser, plain, o.cycle);
    std::mt19937_64 rehome_rng(Mix(o.seed, 0x4000));
    r.homing = sim::HomeAxis(vm, axis, o.homing, rehome_rng);
  }
  sim::InterpolatorOptions io = o.interpolator;
  sim::AxisCorrectionFn correction;
  if (o.table) {
    const PitchErrorTable& table = *o.table;
    if (table.axis != machine.axes[axis].name)
      throw std::invalid_argument(fmt::format("the pitch table is for axis {}, not {}", table.axis, machine.axes[axis].name));
    correction = [&table, &r](double x, int dir) {
      const TableLookup l = LookupError(table, x, dir < 0 ? Direction::kReverse : Direction::kForward);
      if (l.outside) ++r.outside_table_lookups;
      return -l.error_um;
    };
  } else {
    io.mode = sim::FeedForward::kOff;
  }
  sim::CncInterpolator ipo(vm, axis, io, correction);
  std::vector<std::pair<std::string, std::string>> meta = {
      {"state", o.table ? "compensated" : "uncompensated"},
      {"day", std::to_string(o.day)},
      {"homing", fmt::format("{} (reference error {:.3f} um, day 0: {:.3f} um)", sim::HomingMethodName(o.homing),
                             r.homing.offset_um, r.calibration_homing.offset_um)},
  };
  if (o.table) meta.emplace_back("pitch_table", o.table->provenance.empty() ? "given" : o.table->provenance.front());
  r.measurement = RunFineCycle(vm, axis, laser, ipo, o.cycle, meta);
  return r;
}

}  // namespace trueaxis::pitch
