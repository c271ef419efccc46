#include "trueaxis/sim/laser_interferometer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "trueaxis/core/number_text.hpp"

namespace trueaxis::sim {

namespace {
// Edlén: the refractive index of air changes ≈ −0.93 ppm per °C; an air
// sensor reading ΔT too high makes the laser's wavelength correction wrong by
// that much, a length error proportional to the distance from its zero.
constexpr double kAirPpmPerC = 0.93;
}  // namespace

bool LaserOptions::IsValid(std::string* why) const {
  auto fail = [why](const std::string& w) {
    if (why) *why = w;
    return false;
  };
  if (runs < 1 || runs > 20) return fail("runs must be 1–20 (ISO 230-2: 5)");
  if (!(spacing_mm > 0)) return fail("spacing_mm must be positive");
  if (!(overrun_mm >= 0)) return fail("overrun_mm must be ≥ 0");
  if (!(feed_mm_min > 0)) return fail("feed_mm_min must be positive");
  if (!(dwell_s >= 0)) return fail("dwell_s must be ≥ 0");
  if (!(resolution_nm > 0)) return fail("resolution_nm must be positive");
  if (!(noise_nm >= 0)) return fail("noise_nm must be ≥ 0");
  if (!std::isnan(first_mm) && !std::isnan(last_mm) && !(last_mm > first_mm)) return fail("last_mm must exceed first_mm");
  return true;
}

LaserInterferometer::LaserInterferometer(LaserOptions options, std::uint64_t seed) : o_(options), rng_(seed ^ 0x1A5E12ull) {
  std::string why;
  if (!o_.IsValid(&why)) throw std::invalid_argument("laser options: " + why);
  std::normal_distribution<double> nd(0, 1);
  air_error_c_ = nd(rng_) * o_.air_sensor_error_c;
  material_error_c_ = nd(rng_) * o_.material_sensor_error_c;
}

std::vector<double> LaserInterferometer::Targets(const VirtualMachine& vm, std::size_t axis) const {
  const double travel = vm.description().axes.at(axis).travel_mm;
  const double first = std::isnan(o_.first_mm) ? o_.overrun_mm : o_.first_mm;
  const double last = std::isnan(o_.last_mm) ? travel - o_.overrun_mm : o_.last_mm;
  if (first - o_.overrun_mm < -1e-9 || last + o_.overrun_mm > travel + 1e-9 || !(last > first))
    throw std::invalid_argument(fmt::format("laser targets {}–{} mm with overrun {} mm do not fit the travel 0–{} mm of axis {}",
                                            first, last, o_.overrun_mm, travel, vm.AxisName(axis)));
  const int intervals = std::max(1, static_cast<int>(std::round((last - first) / o_.spacing_mm)));
  std::vector<double> t;
  for (int i = 0; i <= intervals; ++i) {
    // Targets on a 1 µm grid so they print cleanly.
    t.push_back(std::round((first + (last - first) * i / intervals) * 1000.0) / 1000.0);
  }
  return t;
}

void LaserInterferometer::Setup(VirtualMachine& vm, std::size_t axis, double datum_mm) {
  const double travel = vm.description().axes.at(axis).travel_mm;
  const double approach = std::max(0.0, datum_mm - std::max(o_.overrun_mm, 1.0));
  vm.MoveTo(axis, approach, o_.feed_mm_min);
  vm.MoveTo(axis, std::min(datum_mm, travel), o_.feed_mm_min);
  vm.Dwell(o_.dwell_s);
  axis_ = static_cast<int>(axis);
  zero_actual_mm_ = vm.ActualMm(axis);
  zero_commanded_mm_ = vm.CommandedMm(axis);
}

double LaserInterferometer::ReadMm(VirtualMachine& vm) {
  if (axis_ < 0) throw std::logic_error("laser: Setup() first");
  const double true_disp_mm = vm.ActualMm(axis_) - zero_actual_mm_;
  double disp = true_disp_mm * (1 + kAirPpmPerC * 1e-6 * air_error_c_);
  if (o_.material_compensation) {
    const double t_mat = vm.NodeTemperatureC("bed") + material_error_c_;
    disp /= 1 + o_.material_cte_um_per_m_c * 1e-6 * (t_mat - 20.0);
  }
  std::normal_distribution<double> nd(0, 1);
  double nm = disp * 1e6 + nd(rng_) * o_.noise_nm;
  nm = std::round(nm / o_.resolution_nm) * o_.resolution_nm;
  return zero_commanded_mm_ + nm * 1e-6;
}

measure::Measurement LaserInterferometer::StartMeasurement(const VirtualMachine& vm) const {
  if (axis_ < 0) throw std::logic_error("laser: Setup() first");
  const auto& ad = vm.description().axes[static_cast<std::size_t>(axis_)];
  measure::Measurement m;
  m.source = "sim";
  m.has_time = true;
  for (std::size_t i = 0; i < vm.ChannelCount(); ++i) m.sensor_names.push_back(vm.ChannelName(i));
  m.SetMeta("axis", ad.name);
  m.SetMeta("machine", vm.description().name);
  m.SetMeta("date", vm.IsoTime());
  m.SetMeta("seed", std::to_string(vm.seed()));
  m.SetMeta("instrument", "trueaxis virtual laser interferometer");
  m.SetMeta("travel_mm", FormatShortest(ad.travel_mm));
  m.SetMeta("lead_mm", FormatShortest(ad.lead_mm));
  m.SetMeta("cte_um_per_m_c", FormatShortest(ad.screw_cte_um_per_m_c));
  m.SetMeta("fixed_end", ad.fixed_end == FixedEnd::kMin ? "min" : "max");
  m.SetMeta("reference_mm", FormatShortest(ad.reference_mm));
  m.SetMeta("laser_zero_mm", FormatShortest(zero_commanded_mm_));
  m.SetMeta("coolant", std::string(CoolantStateName(vm.coolant())));
  return m;
}

measure::MeasurementPoint LaserInterferometer::Reading(VirtualMachine& vm, int run, Direction direction, double target_mm,
                                                       double t0_s) {
  measure::MeasurementPoint p;
  p.run = run;
  p.direction = direction;
  p.target_mm = target_mm;
  const double pos_mm = ReadMm(vm);
  p.deviation_um = std::round((pos_mm - target_mm) * 1e6) / 1000.0;  // laser resolution 1 nm: 3 decimals of µm
  p.time_s = std::round((vm.TimeS() - t0_s) * 10.0) / 10.0;
  std::vector<hw::RawTemperature> raw(vm.ChannelCount());
  hw::TemperatureSource& ts = vm;
  ts.Read(raw);
  // Rounded to 0.1 mK: below every converter's step, and the file stays readable.
  for (const auto& r : raw)
    p.temperatures_c.push_back(r.hardware_fault ? std::numeric_limits<double>::quiet_NaN() : std::round(r.temp_c * 1e4) / 1e4);
  return p;
}

measure::Measurement LaserInterferometer::Measure(VirtualMachine& vm, int runs,
                                                  const std::vector<std::pair<std::string, std::string>>& extra_metadata) {
  if (runs < 1 || runs > 20) throw std::invalid_argument("laser: runs must be 1–20");
  if (axis_ < 0) throw std::logic_error("laser: Setup() first");
  const std::size_t axis = static_cast<std::size_t>(axis_);
  const auto targets = Targets(vm, axis);
  measure::Measurement m = StartMeasurement(vm);
  m.SetMeta("runs", std::to_string(runs));
  m.SetMeta("feed_mm_min", FormatShortest(o_.feed_mm_min));
  m.SetMeta("dwell_s", FormatShortest(o_.dwell_s));
  m.SetMeta("overrun_mm", FormatShortest(o_.overrun_mm));
  m.SetMeta("laser_resolution_nm", FormatShortest(o_.resolution_nm));
  m.SetMeta("material_compensation", o_.material_compensation ? "on" : "off");
  if (o_.material_compensation) m.SetMeta("material_cte_um_per_m_c", FormatShortest(o_.material_cte_um_per_m_c));
  m.SetMeta("ambient_start_c", fmt::format("{:.3f}", vm.AmbientC()));
  for (const auto& [k, v] : extra_metadata) m.SetMeta(k, v);

  const double t0 = vm.TimeS();
  auto record = [&](int run, Direction dir, double target) {
    vm.MoveTo(axis, target, o_.feed_mm_min);
    vm.Dwell(o_.dwell_s);
    m.points.push_back(Reading(vm, run, dir, target, t0));
  };
  RunBidirectionalCycle(targets, runs, o_.overrun_mm, [&](double x) { vm.MoveTo(axis, x, o_.feed_mm_min); }, record);
  m.SetMeta("duration_s", FormatShortest(std::round((vm.TimeS() - t0) * 10.0) / 10.0));
  return m;
}

void RunBidirectionalCycle(const std::vector<double>& targets, int runs, double overrun_mm,
                           const std::function<void(double)>& move_to,
                           const std::function<void(int, Direction, double)>& record) {
  if (targets.empty()) throw std::invalid_argument("laser: no target");
  for (int run = 1; run <= runs; ++run) {
    move_to(targets.front() - overrun_mm);
    for (double t : targets) record(run, Direction::kForward, t);
    move_to(targets.back() + overrun_mm);
    for (auto it = targets.rbegin(); it != targets.rend(); ++it) record(run, Direction::kReverse, *it);
  }
}

}  // namespace trueaxis::sim
