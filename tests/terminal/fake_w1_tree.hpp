#pragma once
// A fake Linux 1-Wire sysfs tree in a temporary directory: one directory per
// sensor holding a w1_slave file the test rewrites between reads, as the
// kernel's w1_therm driver would produce it.
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "trueaxis/terminal/one_wire_temperature_source.hpp"

namespace trueaxis::terminal::testing {

// The two w1_slave lines for a temperature in milli-°C (scratchpad bytes as a
// DS18B20 would hold them; the kernel's CRC verdict as given).
inline std::string W1SlaveText(long milli_c, bool crc_ok = true) {
  const int raw = static_cast<int>(milli_c * 16 / 1000);  // 1/16 °C
  const std::string bytes = fmt::format("{:02x} {:02x} 4b 46 7f ff 0c 10 1c", raw & 0xFF, (raw >> 8) & 0xFF);
  return fmt::format("{} : crc=1c {}\n{} t={}\n", bytes, crc_ok ? "YES" : "NO", bytes, milli_c);
}

inline const std::string kA = "28-0316a2794aff";
inline const std::string kB = "28-0416b1c2d3e4";

class FakeW1Tree : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = std::filesystem::temp_directory_path() /
            ("trueaxis_w1_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "w1_bus_master1");
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  void Write(const std::string& id, const std::string& text) {
    std::filesystem::create_directories(root_ / id);
    std::ofstream(root_ / id / "w1_slave", std::ios::binary | std::ios::trunc) << text;
  }
  void Set(const std::string& id, long milli_c, bool crc_ok = true) { Write(id, W1SlaveText(milli_c, crc_ok)); }
  void Remove(const std::string& id) { std::filesystem::remove_all(root_ / id); }
  std::string root() const { return root_.string(); }
  // Sensors kA and kB of this tree as channels x_nut and spindle.
  OneWireOptions TwoSensors() const {
    OneWireOptions o;
    o.root = root();
    o.sensors = {{kA, "x_nut"}, {kB, "spindle"}};
    return o;
  }

  std::filesystem::path root_;
};

}  // namespace trueaxis::terminal::testing
