#pragma once
// The fixed model the export tests and golden files use: axis X, 0…400 mm,
// Px = 0, cubic forward error, reverse = forward + 6 µm (lost motion) + a
// little shape, thermal gains for coolant off and flood.
#include <string>

#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::exporter::testing {

inline model::AxisModel ExampleAxis() {
  model::AxisModel a;
  a.axis = "X";
  a.reference_position_mm = 0;
  a.key_sensors = {"nut", "bearing"};
  a.baseline_temp_c = {20, 20};
  auto& fwd = a.directions[0];
  fwd.geometric.kind = model::GeometricError::Kind::kPolynomial;
  fwd.geometric.center_mm = 200;
  fwd.geometric.half_span_mm = 200;
  fwd.geometric.coefficients_um = {2.0, -8.0, 3.0, 1.5};
  fwd.thermal = {{CoolantState::kOff, {-0.010, -0.004}, 0}, {CoolantState::kFlood, {-0.005, -0.002}, 0}};
  auto& rev = a.directions[1];
  rev.geometric = fwd.geometric;
  rev.geometric.coefficients_um = {8.0, -7.0, 2.5, 1.5};
  rev.thermal = fwd.thermal;
  return a;
}

inline model::CompositeModel ExampleModel() {
  model::CompositeModel m;
  m.machine = "test-vmc";
  m.created_utc = "2026-11-22T00:00:00Z";
  m.generator = "trueaxis export tests";
  m.axes.push_back(ExampleAxis());
  return m;
}

}  // namespace trueaxis::exporter::testing
