#pragma once
// The runtime tests' fixtures: the shared mock hardware (tests/support/mock_hardware.hpp) and a test model.
#include <cmath>
#include <string>
#include <vector>

#include "../support/mock_hardware.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/runtime/compensator.hpp"

namespace trueaxis::runtime::testing {

using trueaxis::testing::MockCnc;
using trueaxis::testing::MockTemperatures;

// An axis model with a clear geometric shape, a reversal difference, a
// thermal fan about Px and an ambient term, so every path of the cycle moves the output.
inline model::AxisModel TestAxisModel(const std::string& name, double geometric_scale = 1.0) {
  model::AxisModel a;
  a.axis = name;
  a.reference_position_mm = 0;
  a.key_sensors = {"nut", "bearing"};
  a.baseline_temp_c = {20, 20};
  a.ambient_sensor = "ambient";
  a.ambient_baseline_c = 20;
  a.rho_um_per_mm_per_c = 0.0115;
  for (int d = 0; d < 2; ++d) {
    auto& dm = a.directions[d];
    dm.geometric.center_mm = 250;
    dm.geometric.half_span_mm = 250;
    dm.geometric.coefficients_um = {geometric_scale * (d == 0 ? 4.0 : -2.0), geometric_scale * 6.0, geometric_scale * -1.5};
    dm.thermal = {{CoolantState::kOff, {-0.010, -0.004}, 0}, {CoolantState::kFlood, {-0.005, -0.002}, 0}};
  }
  return a;
}

inline std::shared_ptr<const model::CompositeModel> TestModel(double geometric_scale = 1.0, std::vector<std::string> axes = {"X", "Y"}) {
  auto m = std::make_shared<model::CompositeModel>();
  m->machine = "test";
  for (const auto& a : axes) m->axes.push_back(TestAxisModel(a, geometric_scale));
  return m;
}

// One axis X standing at 400 mm (forward), channels ambient / nut / bearing at 20 °C, and a
// compensator that lets any correction through within one cycle and, as the step judges no value
// (the mock's verdicts are the test's), accepts stepped temperatures:
// what the model asks for is what `desired_um` shows, cycle by cycle. A fallback model takes over
// with its own prediction at once unless `fallback_handover_s` > 0.
struct OneAxisRig {
  explicit OneAxisRig(double fallback_handover_s = 0) : cnc({"X"}), temps({"ambient", "nut", "bearing"}, 20.0) {
    CompensatorOptions o;
    o.shaper.max_step_um = 1000;
    o.shaper.max_correction_um = 500;
    o.sensor.fallback_handover_s = fallback_handover_s;
    comp = Compensator::ForHardware(o, cnc, temps, {});
    cnc.axes[0] = {400, +1, true};
  }
  MockCnc cnc;
  MockTemperatures temps;
  std::unique_ptr<Compensator> comp;
};

}  // namespace trueaxis::runtime::testing
