#pragma once
// A short, quiet test axis for the pitch tests: strong lead harmonics (so a
// late correction shows), fast to measure; `axis_extra` adds [[axis]] keys
// (e.g. the home switch's scatter).
#include <string>

#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::pitch::testing {

inline std::string PitchMachineToml(const std::string& axis_extra = "") {
  return R"(
[machine]
name = "pitch-test"
serial_seed = 11
start = 2026-03-02T07:00:00

[ambient]
mean_c = 20.0
seasonal_amplitude_c = 0
daily_amplitude_c = 0
weather_amplitude_c = 0

[[axis]]
name = "X"
travel_mm = 130
lead_mm = 5
backlash_um = 4
homing_repeatability_um = 0.2
)" + axis_extra + R"(
[axis.pitch]
progressive_um = -15
curvature_um = 3
lead_harmonics_um = [2.0, 0.6]
random_um = 2.0
random_wavelength_mm = 40
flank_difference_um = 0.5
)";
}

inline sim::MachineDescription PitchMachine(const std::string& axis_extra = "") {
  return sim::ParseMachineToml(PitchMachineToml(axis_extra), "pitch-test.toml");
}

}  // namespace trueaxis::pitch::testing
