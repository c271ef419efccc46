#pragma once
// In-test fakes of the hardware interfaces: plain state the test sets, and a
// record of what the compensator wrote. Read/Write allocate nothing (the
// no-allocation test runs through them).
#include <cmath>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"
#include "trueaxis/model/composite_model.hpp"

namespace trueaxis::runtime::testing {

class FakeCnc : public hw::CncLink {
 public:
  explicit FakeCnc(std::vector<std::string> names) : names_(std::move(names)), axes(names_.size()), cnc_value_um(names_.size(), 0.0), attempted_um(names_.size(), 0.0) {
    machine.compensation_enabled = true;
  }
  std::size_t AxisCount() const override { return names_.size(); }
  std::string AxisName(std::size_t i) const override { return names_[i]; }
  bool Read(std::span<hw::AxisState> out, hw::CncState& m) override {
    ++reads;
    if (fail_read) return false;
    for (std::size_t i = 0; i < axes.size(); ++i) out[i] = axes[i];
    m = machine;
    return true;
  }
  bool WriteCompensation(std::span<const double> c) override {
    ++write_attempts;
    for (std::size_t i = 0; i < c.size(); ++i) attempted_um[i] = c[i];
    if (fail_write) return false;
    ++writes;
    for (std::size_t i = 0; i < c.size(); ++i) cnc_value_um[i] = c[i];
    return true;
  }

  std::vector<std::string> names_;
  std::vector<hw::AxisState> axes;
  hw::CncState machine;
  bool fail_read = false;
  bool fail_write = false;
  std::vector<double> cnc_value_um;   // what the CNC holds (successful writes only)
  std::vector<double> attempted_um;   // last value offered, even if the write failed
  long reads = 0, writes = 0, write_attempts = 0;
};

class FakeTemps : public hw::TemperatureSource {
 public:
  FakeTemps(std::vector<std::string> names, double initial_c) : names_(std::move(names)), values(names_.size()) {
    for (auto& v : values) v.temp_c = initial_c;
  }
  std::size_t ChannelCount() const override { return names_.size(); }
  std::string ChannelName(std::size_t i) const override { return names_[i]; }
  bool Read(std::span<hw::RawTemperature> out) override {
    if (fail) return false;
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
    return true;
  }
  void Set(const std::string& name, double c) {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) values[i].temp_c = c;
  }
  void SetFault(const std::string& name, bool f) {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == name) values[i].hardware_fault = f;
  }
  std::vector<std::string> names_;
  std::vector<hw::RawTemperature> values;
  bool fail = false;
};

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

}  // namespace trueaxis::runtime::testing
