// The virtual machine tool behind the MODBUS terminal, reached only through
// ModbusCncLink / ModbusTemperatureSource: a compensation written over the
// wire moves the (virtual) table by that amount. The VM is not thread-safe, so
// everything that touches it runs on the server's machine thread (the advance
// hook), and the test sees it through a mutex-guarded snapshot.
#include <gtest/gtest.h>

#include <cmath>
#include <mutex>

#include "modbus_test_server.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/sim/machine_description.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::drivers {
namespace {

// A quiet two-axis machine (docs/machine-file.md): no weather, so an idle
// second changes nothing but what the test writes.
const char* kMachineToml = R"(
[machine]
name = "modbus-test"
serial_seed = 7
start = 2026-03-02T07:00:00

[ambient]
mean_c = 20.0
seasonal_amplitude_c = 0
daily_amplitude_c = 0
weather_amplitude_c = 0

[[axis]]
name = "X"
travel_mm = 600
lead_mm = 10
fixed_end = "min"
backlash_um = 6

[[axis]]
name = "Y"
travel_mm = 400
lead_mm = 12
fixed_end = "max"
backlash_um = 3
)";

struct Snapshot {
  double actual_mm[2] = {0, 0};
  double commanded_mm[2] = {0, 0};
  double correction_um[2] = {0, 0};
  double time_s = 0;
  double move_x_to_mm = std::nan("");  // a move the machine thread commands at its next advance
};

TEST(VirtualMachineOverModbus, CompensationWrittenOverTheWireMovesTheTable) {
  sim::VirtualMachine vm(sim::ParseMachineToml(kMachineToml, "modbus-test.toml"), 11);
  std::vector<std::string> channel_names;
  for (std::size_t c = 0; c < vm.ChannelCount(); ++c) channel_names.push_back(vm.ChannelName(c));
  ASSERT_GE(channel_names.size(), 4u);

  std::mutex mu;
  Snapshot snap;
  ModbusMachineServerOptions so;
  std::unique_ptr<ModbusMachineServer> server;
  std::string error;
  // StartServer builds a fresh server per port attempt, so the hook is set by
  // constructing here instead.
  std::mt19937 rng(std::random_device{}());
  for (int i = 0; i < 50 && !server; ++i) {
    so.port = std::uniform_int_distribution<int>(20000, 59999)(rng);
    auto s = std::make_unique<ModbusMachineServer>(&vm, &vm, so);
    s->SetAdvance([&](double elapsed_s) {
      std::lock_guard<std::mutex> l(mu);
      if (std::isfinite(snap.move_x_to_mm)) vm.CommandMove(0, snap.move_x_to_mm, 600);
      snap.move_x_to_mm = std::nan("");
      vm.Advance(elapsed_s);  // real time, time scale 1
      for (std::size_t a = 0; a < 2; ++a) {
        snap.actual_mm[a] = vm.ActualMm(a);
        snap.commanded_mm[a] = vm.CommandedMm(a);
        snap.correction_um[a] = vm.CorrectionUm(a);
      }
      snap.time_s = vm.TimeS();
    });
    if (s->Start(&error)) server = std::move(s);
  }
  ASSERT_NE(server, nullptr) << error;
  auto get = [&] {
    std::lock_guard<std::mutex> l(mu);
    return snap;
  };

  ModbusCncLinkOptions lo;
  lo.endpoint.port = so.port;
  lo.endpoint.response_timeout_s = 1.0;  // shared, loaded build machine
  lo.axis_names = {"X", "Y"};
  ModbusCncLink link(lo);
  std::vector<hw::AxisState> axes(2);
  hw::CncState state;
  ASSERT_TRUE(testing::WaitFor([&] { return link.Read(axes, state); })) << link.last_error();
  EXPECT_TRUE(state.compensation_enabled);
  EXPECT_NEAR(axes[0].position_mm, get().commanded_mm[0], 1e-4);  // the CNC's own coordinate

  // Take up the play in + first, so the next step is a pure table move.
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{5.0, -3.0}));
  ASSERT_TRUE(testing::WaitFor([&] { return std::abs(get().correction_um[0] - 5.0) < 1e-9; }));
  const Snapshot before = get();
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{25.0, -13.0}));
  ASSERT_TRUE(testing::WaitFor([&] { return std::abs(get().correction_um[0] - 25.0) < 1e-9; }));
  const Snapshot after = get();
  EXPECT_NEAR(after.correction_um[1], -13.0, 1e-9);
  // The table moved by the added correction (+20 µm on X, −10 µm on Y); the CNC
  // coordinate did not. Idle at 20 °C, thermal drift in a second is far below 0.5 µm.
  EXPECT_NEAR((after.actual_mm[0] - before.actual_mm[0]) * 1000.0, 20.0, 0.5);
  EXPECT_NEAR((after.actual_mm[1] - before.actual_mm[1]) * 1000.0, -10.0, 0.5);
  EXPECT_EQ(after.commanded_mm[0], before.commanded_mm[0]);
  // And the PMC window reports what the machine applies.
  ASSERT_TRUE(testing::WaitFor([&] { return link.Read(axes, state) && std::abs(link.applied_um()[0] - 25.0) < 1e-9; }));

  // The programmed direction: not known before the first move; after a move towards + and one
  // back towards −, the window says − while the axis stands, whatever the compensation does.
  EXPECT_EQ(axes[0].programmed_direction, 0);
  const double from_mm = get().commanded_mm[0];
  const auto move_x = [&](double to_mm) {
    {
      std::lock_guard<std::mutex> l(mu);
      snap.move_x_to_mm = to_mm;
    }
    return testing::WaitFor([&] { return std::abs(get().commanded_mm[0] - to_mm) < 1e-9; }) &&
           testing::WaitFor([&] { return link.Read(axes, state) && std::abs(axes[0].position_mm - to_mm) < 1e-6 && !axes[0].moving; });
  };
  ASSERT_TRUE(move_x(from_mm + 3));
  EXPECT_EQ(axes[0].programmed_direction, +1);
  ASSERT_TRUE(move_x(from_mm + 1));
  EXPECT_EQ(axes[0].programmed_direction, -1);
  EXPECT_EQ(axes[1].programmed_direction, 0);  // Y never moved
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{30.0, -13.0}));  // a nudge towards +
  ASSERT_TRUE(testing::WaitFor([&] { return link.Read(axes, state) && std::abs(link.applied_um()[0] - 30.0) < 1e-9; }));
  EXPECT_EQ(axes[0].programmed_direction, -1);

  // The machine's sensors arrive as ADAM-6015 channels.
  ModbusTemperatureSourceOptions to;
  to.endpoint.port = so.port;
  to.endpoint.response_timeout_s = 1.0;
  to.channel_names = channel_names;
  to.unit_ids.clear();
  for (std::size_t k = 0; k < server->RtdModuleCount(); ++k) to.unit_ids.push_back(so.first_rtd_unit_id + static_cast<int>(k));
  ModbusTemperatureSource rtd(to);
  std::vector<hw::RawTemperature> t(channel_names.size());
  ASSERT_TRUE(rtd.Read(t)) << rtd.last_error();
  for (std::size_t c = 0; c < t.size(); ++c) {
    EXPECT_FALSE(t[c].hardware_fault) << channel_names[c];
    EXPECT_GT(t[c].temp_c, 15.0) << channel_names[c];
    EXPECT_LT(t[c].temp_c, 30.0) << channel_names[c];
  }
  EXPECT_GT(get().time_s, 0.0);
  server->Stop();
}

}  // namespace
}  // namespace trueaxis::drivers
