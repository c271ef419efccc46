#pragma once
// The one mock hardware of the tests and benches: a CNC link and a temperature source whose state
// the test sets in plain fields, with a record of what was written and switches for link faults.
// Read/Write allocate nothing (the no-allocation tests run through them). Not thread-safe: a test
// that shares one with another thread hands it over (e.g. it is read only by an I/O worker).
// (tests/drivers/fake_machine.hpp keeps a locked variant for servers whose machine thread and the
// test thread both touch it.)
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::testing {

class MockCnc : public hw::CncLink {
 public:
  explicit MockCnc(std::vector<std::string> names) : names_(std::move(names)), axes(names_.size()), cnc_value_um(names_.size(), 0.0), attempted_um(names_.size(), 0.0) {
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

class MockTemperatures : public hw::TemperatureSource {
 public:
  MockTemperatures(std::vector<std::string> names, double initial_c) : names_(std::move(names)), values(names_.size()) {
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

}  // namespace trueaxis::testing
