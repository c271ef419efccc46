#pragma once
// A small test machine: one or two axes, quiet ambient, so physics checks
// run in milliseconds and are not masked by weather.
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
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

// A machine file that must be refused: by an InputError naming bad.toml, `line` and `field`, and
// saying `why` (empty: not checked).
struct BadMachineFile {
  const char* what;
  std::string toml;
  int line;
  const char* field;
  const char* why = "";
};

inline void ExpectBad(const BadMachineFile& c) {
  try {
    ParseMachineToml(c.toml, "bad.toml");
    ADD_FAILURE() << c.what << ": no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "bad.toml") << c.what;
    EXPECT_EQ(e.line(), c.line) << c.what << ": " << e.what();
    EXPECT_EQ(e.field(), c.field) << c.what << ": " << e.what();
    EXPECT_NE(std::string(e.what()).find(c.why), std::string::npos) << c.what << ": " << e.what();
  }
}

}  // namespace trueaxis::sim::testing
