#pragma once
// A small test machine: one or two axes, quiet ambient, so physics checks
// run in milliseconds and are not masked by weather.
#include <string>

#include "trueaxis/sim/machine_description.hpp"

namespace trueaxis::sim::testing {

inline std::string TestMachineToml(const std::string& extra_axis = "", const std::string& ambient = "") {
  return R"(
[machine]
name = "test-vmc"
serial_seed = 7
start = 2026-03-02T07:00:00

[ambient]
)" + (ambient.empty() ? std::string("mean_c = 20.0\nseasonal_amplitude_c = 0\ndaily_amplitude_c = 0\nweather_amplitude_c = 0\n") : ambient) +
         R"(
[[axis]]
name = "X"
travel_mm = 600
lead_mm = 10
fixed_end = "min"
backlash_um = 6
homing_repeatability_um = 0.5

[[axis]]
name = "Y"
travel_mm = 400
lead_mm = 12
fixed_end = "max"
backlash_um = 3
)" + extra_axis;
}

inline MachineDescription TestMachine(const std::string& ambient = "") {
  return ParseMachineToml(TestMachineToml("", ambient), "test.toml");
}

}  // namespace trueaxis::sim::testing
