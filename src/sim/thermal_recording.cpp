#include "trueaxis/sim/thermal_recording.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::sim {

bool ThermalRecordingOptions::IsValid(std::string* why) const {
  auto fail = [&](const char* text) {
    if (why) *why = text;
    return false;
  };
  if (!(hours > 0 && hours <= 24 * 14)) return fail("hours must be in (0, 336]");
  if (!(interval_s >= 1 && interval_s <= 3600)) return fail("interval_s must be in [1, 3600]");
  if (!(hours * 3600 / interval_s >= 10)) return fail("fewer than 10 samples: lengthen hours or shorten interval_s");
  if (!(position_fraction >= 0 && position_fraction <= 1)) return fail("position_fraction must be in [0, 1]");
  return true;
}

ThermalRecording RecordThermalDay(VirtualMachine& vm, const ThermalRecordingOptions& o) {
  std::string why;
  if (!o.IsValid(&why)) throw InputError("thermal recording options", why);
  const MachineDescription& d = vm.description();
  ThermalRecording rec;
  for (std::size_t i = 0; i < vm.SensorCount(); ++i) rec.sensor_names.push_back(vm.sensor(i).description().name);
  std::vector<double> at_mm;
  for (const auto& a : d.axes) {
    at_mm.push_back(o.position_fraction * a.travel_mm);
    rec.error_names.push_back(fmt::format("{}_at_{:g}mm", a.name, std::round(at_mm.back())));
  }
  const auto samples = static_cast<Eigen::Index>(std::floor(o.hours * 3600 / o.interval_s)) + 1;
  rec.temperatures_c.resize(samples, static_cast<Eigen::Index>(rec.sensor_names.size()));
  rec.errors_um.resize(samples, static_cast<Eigen::Index>(at_mm.size()));
  const double t0 = vm.TimeS();
  auto log = [&](const VirtualMachine& m) {
    const auto row = static_cast<Eigen::Index>(rec.time_s.size());
    if (row >= samples) return;
    rec.time_s.push_back(m.TimeS() - t0);
    rec.coolant.push_back(m.coolant());
    for (std::size_t i = 0; i < m.SensorCount(); ++i) {
      const hw::RawTemperature r = m.sensor(i).Latest();
      rec.temperatures_c(row, static_cast<Eigen::Index>(i)) =
          r.hardware_fault ? std::numeric_limits<double>::quiet_NaN() : r.temp_c;
    }
    for (std::size_t a = 0; a < at_mm.size(); ++a) rec.errors_um(row, static_cast<Eigen::Index>(a)) = m.ErrorAtUm(a, at_mm[a], +1);
  };
  vm.SetLogger(o.interval_s, log);  // logs the first sample at once

  std::mt19937_64 rng(o.programme_seed * 0x9E3779B97F4A7C15ull + 17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double end_s = t0 + o.hours * 3600;
  bool machining = false;  // start cold: the first phase idles or works, as drawn
  while (vm.TimeS() < end_s - 1e-6) {
    machining = !machining ? u(rng) < 0.75 : u(rng) < 0.35;
    const double minutes = 20 + 160 * u(rng);
    const double duration = std::min(minutes * 60, end_s - vm.TimeS());
    if (machining) {
      const double feed = 1000 + 5000 * u(rng), duty = 0.3 + 0.7 * u(rng);
      const CoolantState coolant = u(rng) < 0.35 ? CoolantState::kFlood : CoolantState::kOff;
      vm.SetCoolant(coolant);
      for (std::size_t a = 0; a < d.axes.size(); ++a)
        vm.CommandReciprocate(a, 0.1 * d.axes[a].travel_mm, 0.9 * d.axes[a].travel_mm, feed, duty);
      rec.programme.push_back(fmt::format("{:.2f} h: machining {:.0f} min at {:.0f} mm/min, duty {:.2f}, coolant {}",
                                          (vm.TimeS() - t0) / 3600, duration / 60, feed, duty, CoolantStateName(coolant)));
    } else {
      for (std::size_t a = 0; a < d.axes.size(); ++a) vm.CommandStop(a);
      vm.SetCoolant(CoolantState::kOff);
      rec.programme.push_back(fmt::format("{:.2f} h: idle {:.0f} min", (vm.TimeS() - t0) / 3600, duration / 60));
    }
    vm.Advance(duration);
  }
  for (std::size_t a = 0; a < d.axes.size(); ++a) vm.CommandStop(a);
  vm.SetLogger(0, nullptr);
  const auto rows = static_cast<Eigen::Index>(rec.time_s.size());
  rec.temperatures_c.conservativeResize(rows, Eigen::NoChange);
  rec.errors_um.conservativeResize(rows, Eigen::NoChange);
  return rec;
}

}  // namespace trueaxis::sim
