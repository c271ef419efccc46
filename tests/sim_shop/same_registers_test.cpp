// Both terminal servers — drivers::ModbusMachineServer (`sim serve`, `terminal`) and the virtual
// shop's terminals (`sim shop`) — answer the same registers for the same machine: one virtual
// machine of a virtual shop is also served through a ModbusMachineServer, and the same client
// reads both, then writes the same command to both.
#include <modbus.h>

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "drivers/modbus_test_server.hpp"
#include "drivers/peers/pymodbus_peer.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"
#include "trueaxis/sim/virtual_machine.hpp"
#include "trueaxis/sim_shop/virtual_shop.hpp"

namespace trueaxis::sim {
namespace {

namespace pmc = drivers::pmc;
namespace adam = drivers::adam6015;

using drivers::testing::WaitFor;

// Every register a client can read from one terminal.
struct Registers {
  std::vector<std::uint16_t> ir, hr;
  std::vector<std::array<std::uint16_t, adam::kRegisterCount>> modules;
  std::vector<std::array<std::uint8_t, adam::kCoilCount>> coils;
};

Registers ReadAll(int port, std::size_t axes, std::size_t modules) {
  Registers r;
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  EXPECT_NE(ctx, nullptr);
  EXPECT_EQ(modbus_connect(ctx), 0) << modbus_strerror(errno);
  modbus_set_slave(ctx, pmc::kDefaultUnitId);
  r.ir.resize(static_cast<std::size_t>(pmc::InputWindowLength(axes)));
  r.hr.resize(static_cast<std::size_t>(drivers::PmcHoldingLength(axes)));
  EXPECT_EQ(modbus_read_input_registers(ctx, 0, static_cast<int>(r.ir.size()), r.ir.data()), static_cast<int>(r.ir.size()));
  EXPECT_EQ(modbus_read_registers(ctx, 0, static_cast<int>(r.hr.size()), r.hr.data()), static_cast<int>(r.hr.size()));
  r.modules.resize(modules);
  r.coils.resize(modules);
  for (std::size_t k = 0; k < modules; ++k) {
    modbus_set_slave(ctx, 2 + static_cast<int>(k));
    // 125 registers at most per request
    for (int a = 0; a < adam::kRegisterCount; a += 100) {
      const int n = std::min(100, adam::kRegisterCount - a);
      EXPECT_EQ(modbus_read_registers(ctx, a, n, r.modules[k].data() + a), n);
    }
    EXPECT_EQ(modbus_read_bits(ctx, 0, adam::kCoilCount, r.coils[k].data()), adam::kCoilCount);
  }
  modbus_close(ctx);
  modbus_free(ctx);
  return r;
}

std::unique_ptr<drivers::ModbusMachineServer> ServeThrough(VirtualShop& shop) {
  std::mt19937 rng(std::random_device{}());
  drivers::ModbusMachineServerOptions o;
  for (int attempt = 0; attempt < 50; ++attempt) {
    o.port = 20000 + static_cast<int>(rng() % 40000);
    VirtualMachine& vm = shop.Machine(0);
    auto server = std::make_unique<drivers::ModbusMachineServer>(&vm, &vm, o);
    server->ShareMachineWith(&shop.MachineMutex());
    if (server->Start(nullptr)) return server;
  }
  return nullptr;
}

std::unique_ptr<VirtualShop> StartFrozenShop() {
  VirtualShopOptions o;
  o.machine_files = {std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml"};
  o.machines = 1;
  o.time_scale = 1e-9;  // the machine stands still: both terminals read the same state
  o.tick_s = 10;        // one tick at start, one at once in the loop, then none for 10 s
  std::mt19937 rng(std::random_device{}());
  for (int attempt = 0; attempt < 30; ++attempt) {
    o.base_port = 20000 + static_cast<int>(rng() % 40000);
    auto shop = std::make_unique<VirtualShop>(o);
    if (shop->Start(nullptr)) return shop;
  }
  return nullptr;
}

TEST(TerminalServers, AnswerTheSameRegistersForTheSameMachine) {
  auto shop = StartFrozenShop();
  ASSERT_NE(shop, nullptr);
  ASSERT_TRUE(WaitFor([&] { return shop->Stats().ticks >= 2; }));
  auto server = ServeThrough(*shop);
  ASSERT_NE(server, nullptr);
  ASSERT_TRUE(WaitFor([&] { return server->Stats().exchanges >= 3; }));
  const VirtualMachineInfo info = shop->Machines().at(0);
  const std::size_t axes = info.axes.size(), modules = drivers::RtdModulesFor(info.channels.size());
  ASSERT_GE(modules, 1u);

  const Registers a = ReadAll(info.port, axes, modules);
  const Registers b = ReadAll(server->options().port, axes, modules);
  // The PMC window: every register but the heartbeat (each terminal counts its own exchanges)
  // and the age of the machine state (the shop reads its machine in the tick that publishes).
  for (std::size_t i = 0; i < a.ir.size(); ++i) {
    if (i == pmc::kIrHeartbeatHi || i == pmc::kIrHeartbeatLo || i == pmc::kIrReadAgeMs) continue;
    EXPECT_EQ(a.ir[i], b.ir[i]) << "input register " << i;
  }
  // not zeros against zeros: the machine stands somewhere and its sensors read something
  bool some_position = false;
  for (std::size_t x = 0; x < axes; ++x)
    some_position = some_position || a.ir[pmc::InputAxisRegister(x, pmc::kIrAxisPositionHi)] != 0 ||
                    a.ir[pmc::InputAxisRegister(x, pmc::kIrAxisPositionLo)] != 0;
  EXPECT_TRUE(some_position);
  EXPECT_NE(a.modules[0][adam::kAiValueAddress], 0);
  EXPECT_NE(a.modules[0][adam::kAiMaxAddress], 0);
  EXPECT_NE(a.ir[pmc::kIrStatus] & pmc::kStatusMachineReadOk, 0);
  EXPECT_NE(a.ir[pmc::kIrStatus] & pmc::kStatusTemperatureReadOk, 0);
  EXPECT_EQ(a.hr, b.hr);
  for (std::size_t k = 0; k < modules; ++k) {
    for (int i = 0; i < adam::kRegisterCount; ++i) EXPECT_EQ(a.modules[k][i], b.modules[k][i]) << "module " << k << " register " << i;
    for (int i = 0; i < adam::kCoilCount; ++i) EXPECT_EQ(a.coils[k][i], b.coils[k][i]) << "module " << k << " coil " << i;
  }

  // The same client decodes both to the same state, and its command reaches the CNC through both.
  const std::vector<double> command = {12.3, -4.5, 0.7};
  ASSERT_EQ(command.size(), axes);
  std::vector<std::vector<double>> applied;
  for (int port : {info.port, server->options().port}) {
    drivers::ModbusCncLinkOptions co;
    co.endpoint.port = port;
    co.endpoint.response_timeout_s = 1.0;
    co.axis_names = info.axes;
    drivers::ModbusCncLink link(co);
    ASSERT_TRUE(link.Connect()) << link.last_error();
    std::vector<hw::AxisState> st(axes);
    hw::CncState machine;
    ASSERT_TRUE(link.Read(st, machine)) << link.last_error();
    std::vector<hw::AxisState> direct(axes);
    hw::CncState direct_machine;
    {
      std::lock_guard<std::mutex> lock(shop->MachineMutex());
      ASSERT_TRUE(shop->Machine(0).Read(direct, direct_machine));
    }
    EXPECT_EQ(machine.coolant, direct_machine.coolant);
    for (std::size_t x = 0; x < axes; ++x) {
      EXPECT_NEAR(st[x].position_mm, direct[x].position_mm, 0.00005 + 1e-12);
      EXPECT_EQ(st[x].servo_direction, direct[x].servo_direction);
      EXPECT_EQ(st[x].moving, direct[x].moving);
      EXPECT_EQ(st[x].programmed_direction, direct[x].programmed_direction);
      EXPECT_EQ(st[x].travel_mm, std::floor(direct[x].travel_mm));
    }
    drivers::ModbusTemperatureSourceOptions to;
    to.endpoint = co.endpoint;
    to.unit_ids = drivers::RtdModuleUnitIds(2, info.channels.size());
    to.channel_names = info.channels;
    drivers::ModbusTemperatureSource temps(to);
    std::vector<hw::RawTemperature> raw(info.channels.size()), truth(info.channels.size());
    ASSERT_TRUE(temps.Read(raw)) << temps.last_error();
    {
      std::lock_guard<std::mutex> lock(shop->MachineMutex());
      ASSERT_TRUE(shop->Machine(0).Read(std::span<hw::RawTemperature>(truth)));
    }
    for (std::size_t c = 0; c < raw.size(); ++c) {
      EXPECT_EQ(raw[c].hardware_fault, truth[c].hardware_fault) << info.channels[c];
      if (!truth[c].hardware_fault) EXPECT_NEAR(raw[c].temp_c, truth[c].temp_c, 0.0031) << info.channels[c];
    }

    ASSERT_TRUE(link.WriteCompensation(command)) << link.last_error();
    ASSERT_TRUE(WaitFor([&] {
      return link.Read(st, machine) && std::abs(link.applied_um()[0] - command[0]) < 1e-9;
    })) << "port " << port;
    applied.push_back(link.applied_um());
  }
  for (std::size_t x = 0; x < axes; ++x) {
    EXPECT_NEAR(applied[0][x], command[x], 1e-9);
    EXPECT_NEAR(applied[1][x], command[x], 1e-9);
  }
  server->Stop();
  shop->Stop();
}

TEST(TerminalServers, TheVirtualShopAnswersOneTransactionPerCycle) {
  auto shop = StartFrozenShop();
  ASSERT_NE(shop, nullptr);
  const VirtualMachineInfo info = shop->Machines().at(0);
  drivers::ModbusCncLinkOptions co;
  co.endpoint.port = info.port;
  co.endpoint.response_timeout_s = 1.0;
  co.axis_names = info.axes;
  drivers::ModbusCncLink link(co);
  ASSERT_TRUE(link.Connect()) << link.last_error();
  std::vector<hw::AxisState> st(info.axes.size());
  hw::CncState machine;
  const std::vector<double> command = {-3.3, 8.8, 0.1};
  const auto before = shop->Stats().requests;
  ASSERT_TRUE(link.WriteAndRead(command, st, machine)) << link.last_error();
  EXPECT_EQ(shop->Stats().requests, before + 1);
  EXPECT_TRUE(link.read_write_answered());
  // the virtual shop hands the command to its machine before it answers the read part
  for (std::size_t x = 0; x < command.size(); ++x) EXPECT_NEAR(link.applied_um()[x], command[x], 1e-9);
  const std::vector<double> applied = shop->AppliedUm(0);
  for (std::size_t x = 0; x < command.size(); ++x) EXPECT_NEAR(applied[x], command[x], 1e-9);

  // an independent peer (pymodbus) reads the same window through FC 23 as through FC 04
  const nlohmann::json j = trueaxis::testing::RunPymodbusPeer("--read-write " + std::to_string(info.port) + " 3 1.0 2.0 3.0");
  ASSERT_FALSE(j.contains("error")) << j.dump();
  const auto copy = j["copy"].get<std::vector<int>>(), window = j["window"].get<std::vector<int>>();
  ASSERT_EQ(copy.size(), static_cast<std::size_t>(pmc::InputWindowLength(3)));
  ASSERT_EQ(window.size(), copy.size());
  // a frozen machine: the same registers, applied values included (only the heartbeat may move)
  for (std::size_t i = 0; i < copy.size(); ++i)
    if (i != pmc::kIrHeartbeatHi && i != pmc::kIrHeartbeatLo) EXPECT_EQ(copy[i], window[i]) << "register " << i;
  EXPECT_EQ(copy[pmc::InputAxisRegister(2, pmc::kIrAxisAppliedLo)], 30);  // 3.0 µm = 30 counts
  EXPECT_NEAR(shop->AppliedUm(0)[2], 3.0, 1e-9);
  shop->Stop();
}

}  // namespace
}  // namespace trueaxis::sim
