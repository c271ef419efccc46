// ModbusMachineServer against the project's own clients over real loopback
// sockets, plus raw libmodbus requests for the refusals a terminal must make.
#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <thread>

#include "modbus_test_server.hpp"
#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"
#include "trueaxis/drivers/pmc_window_map.hpp"
#include "trueaxis/drivers/register_codec.hpp"

namespace trueaxis::drivers {
namespace {

using testing::MockCnc;
using testing::MockTemperatures;
using testing::StartServer;
using testing::WaitFor;

// Tests that expect every request to succeed allow a generous response
// timeout: the build machine is shared and often overloaded.
constexpr double kTestTimeoutS = 1.0;

// A raw libmodbus client for requests the typed clients never send.
struct RawClient {
  modbus_t* ctx;
  RawClient(int port, int unit) {
    ctx = modbus_new_tcp("127.0.0.1", port);
    modbus_set_response_timeout(ctx, 1, 0);
    modbus_set_slave(ctx, unit);
    connected = modbus_connect(ctx) == 0;
  }
  ~RawClient() {
    modbus_close(ctx);
    modbus_free(ctx);
  }
  bool connected = false;
};

class ServerClientTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cnc = std::make_unique<MockCnc>(std::vector<std::string>{"X", "Y", "Z"});
    temps = std::make_unique<MockTemperatures>(9);  // two ADAM-6015 modules: 7 + 2 channels
    std::string error;
    server = StartServer(cnc.get(), temps.get(), options, &error);
    ASSERT_NE(server, nullptr) << error;
    port = server->options().port;
  }
  ModbusCncLinkOptions LinkOptions() const {
    ModbusCncLinkOptions o;
    o.endpoint.port = port;
    o.endpoint.reconnect_interval_s = 0.05;
    o.endpoint.response_timeout_s = kTestTimeoutS;
    o.axis_names = {"X", "Y", "Z"};
    return o;
  }
  ModbusTemperatureSourceOptions TempOptions() const {
    ModbusTemperatureSourceOptions o;
    o.endpoint.port = port;
    o.endpoint.reconnect_interval_s = 0.05;
    o.endpoint.response_timeout_s = kTestTimeoutS;
    o.unit_ids = {2, 3};
    for (int i = 0; i < 9; ++i) o.channel_names.push_back("t" + std::to_string(i));
    return o;
  }
  ModbusMachineServerOptions options;
  std::unique_ptr<MockCnc> cnc;
  std::unique_ptr<MockTemperatures> temps;
  std::unique_ptr<ModbusMachineServer> server;
  int port = 0;
};

TEST_F(ServerClientTest, ClientReadsTheCncStateThroughThePmcWindow) {
  cnc->SetAxis(0, {123.4567, +1, true});
  cnc->SetAxis(1, {-45.00012, -1, false});
  cnc->SetAxis(2, {0.0, 0, false});
  cnc->SetState({CoolantState::kMist, true});
  ModbusCncLink link(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && state.coolant == CoolantState::kMist; })) << link.last_error();
  EXPECT_NEAR(axes[0].position_mm, 123.4567, 0.5e-4);
  EXPECT_EQ(axes[0].servo_direction, 1);
  EXPECT_TRUE(axes[0].moving);
  EXPECT_NEAR(axes[1].position_mm, -45.0001, 0.5e-4);
  EXPECT_EQ(axes[1].servo_direction, -1);
  EXPECT_FALSE(axes[1].moving);
  EXPECT_EQ(axes[2].servo_direction, 0);
  EXPECT_TRUE(state.compensation_enabled);
  // The state follows the machine.
  cnc->SetAxis(0, {-7.5, -1, true});
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && std::abs(axes[0].position_mm + 7.5) < 1e-6; }));
  EXPECT_EQ(axes[0].servo_direction, -1);
}

// The optional programmed-direction register (input register 8): one bit per axis and direction,
// written by the terminal from its CNC link and read back by ModbusCncLink; 0 (a CNC that does not
// tell, or an older terminal whose reserved register reads 0) is "not known".
TEST_F(ServerClientTest, ProgrammedDirectionsTravelInTheirRegister) {
  hw::AxisState x{300.0, +1, false}, y{10.0, -1, false}, z{0.0, 0, false};
  x.programmed_direction = -1;  // standing after a move back: the servo register still shows +
  y.programmed_direction = +1;
  cnc->SetAxis(0, x);
  cnc->SetAxis(1, y);
  cnc->SetAxis(2, z);
  ModbusCncLink link(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && axes[0].programmed_direction == -1; })) << link.last_error();
  EXPECT_EQ(axes[0].servo_direction, 1);
  EXPECT_EQ(axes[1].programmed_direction, 1);
  EXPECT_EQ(axes[2].programmed_direction, 0);
  RawClient raw(port, pmc::kDefaultUnitId);
  ASSERT_TRUE(raw.connected);
  std::uint16_t bits = 0;
  ASSERT_EQ(modbus_read_input_registers(raw.ctx, pmc::kIrProgrammedDirection, 1, &bits), 1);
  EXPECT_EQ(bits, (1u << 1) | (1u << (8 + 0)));  // Y towards +, X towards −
  // Both bits of an axis set: inconsistent, read as not known.
  EXPECT_EQ(pmc::ProgrammedDirection(static_cast<std::uint16_t>((1u << 2) | (1u << 10)), 2), 0);
  x.programmed_direction = 0;  // the CNC stops telling
  cnc->SetAxis(0, x);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && axes[0].programmed_direction == 0; }));
  EXPECT_EQ(axes[1].programmed_direction, 1);
}

TEST_F(ServerClientTest, CompensationWrittenByTheClientReachesTheCncLink) {
  ModbusCncLink link(LinkOptions());
  const std::vector<double> corr = {12.3, -4.56, 0.1};
  ASSERT_TRUE(link.WriteCompensation(corr)) << link.last_error();
  ASSERT_TRUE(WaitFor([&] { auto c = cnc->Compensation(); return std::abs(c[1] + 4.6) < 1e-9; }));
  const auto got = cnc->Compensation();
  EXPECT_NEAR(got[0], 12.3, 1e-9);
  EXPECT_NEAR(got[1], -4.6, 1e-9);  // quantised to 0.1 µm
  EXPECT_NEAR(got[2], 0.1, 1e-9);
  // The window reports what the CNC applies.
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && std::abs(link.applied_um()[0] - 12.3) < 1e-9; }));
  EXPECT_NEAR(link.applied_um()[1], -4.6, 1e-9);
}

TEST_F(ServerClientTest, EnableBitIsAndedWithTheCncsOwnEnable) {
  cnc->SetState({CoolantState::kOff, true});
  ModbusCncLink link(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && state.compensation_enabled; }));
  RawClient raw(port, 1);
  ASSERT_TRUE(raw.connected);
  ASSERT_EQ(modbus_write_register(raw.ctx, pmc::kHrEnable, 0), 1);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && !state.compensation_enabled; }));
  ASSERT_EQ(modbus_write_register(raw.ctx, pmc::kHrEnable, 1), 1);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && state.compensation_enabled; }));
  cnc->SetState({CoolantState::kOff, false});  // the operator switches it off on the CNC
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && !state.compensation_enabled; }));
}

TEST_F(ServerClientTest, OutOfBoundCompensationIsRefusedAndNothingReachesTheCnc) {
  ModbusCncLink link(LinkOptions());
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{5.0, 5.0, 5.0}));
  ASSERT_TRUE(WaitFor([&] { return cnc->Compensation()[0] == 5.0; }));
  const int writes = cnc->Writes();
  EXPECT_FALSE(link.WriteCompensation(std::vector<double>{5.0, 1500.0, 5.0}));  // bound is 1000 µm
  EXPECT_NE(link.last_error().find("Illegal data value"), std::string::npos) << link.last_error();
  EXPECT_TRUE(link.connected());  // an exception answer is not a link fault
  EXPECT_FALSE(link.WriteCompensation(std::vector<double>{std::nan(""), 0.0, 0.0}));
  EXPECT_FALSE(link.WriteCompensation(std::vector<double>{1.0, 2.0}));  // wrong axis count
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(cnc->Writes(), writes);
  EXPECT_EQ(cnc->Compensation(), (std::vector<double>{5.0, 5.0, 5.0}));
  // Still usable.
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{-999.9, 0.0, 999.9}));
  ASSERT_TRUE(WaitFor([&] { return std::abs(cnc->Compensation()[0] + 999.9) < 1e-9; }));
}

TEST_F(ServerClientTest, TemperaturesArriveScaledLikeAnAdam6015WithBurnout) {
  temps->Set(0, 21.25);
  temps->Set(3, -12.0);
  temps->Set(5, 35.0, /*fault=*/true);
  temps->Set(8, 88.8);  // second module, channel 1
  ModbusTemperatureSource source(TempOptions());
  std::vector<hw::RawTemperature> out(9);
  ASSERT_TRUE(WaitFor([&] { return source.Read(out) && std::abs(out[8].temp_c - 88.8) < 0.01; })) << source.last_error();
  const double half_count = AdamResolutionC(*FindRtdRange(adam6015::kDefaultRangeCode)) / 2 + 1e-9;
  EXPECT_NEAR(out[0].temp_c, 21.25, half_count);
  EXPECT_NEAR(out[3].temp_c, -12.0, half_count);
  EXPECT_NEAR(out[8].temp_c, 88.8, half_count);
  EXPECT_NEAR(out[1].temp_c, 20.5, half_count);
  EXPECT_TRUE(out[5].hardware_fault);
  for (int c : {0, 1, 2, 3, 4, 6, 7, 8}) EXPECT_FALSE(out[c].hardware_fault) << c;
  ASSERT_NE(source.ChannelRange(8), nullptr);
  EXPECT_EQ(source.ChannelRange(8)->code, adam6015::kDefaultRangeCode);
  // The fault clears when the sensor is back.
  temps->Set(5, 30.0);
  ASSERT_TRUE(WaitFor([&] { return source.Read(out) && !out[5].hardware_fault; }));
  EXPECT_NEAR(out[5].temp_c, 30.0, half_count);
}

TEST_F(ServerClientTest, TemperatureSourceDownMeansReadFailsAndLeavesOutputUntouched) {
  ModbusTemperatureSource source(TempOptions());
  std::vector<hw::RawTemperature> out(9);
  ASSERT_TRUE(WaitFor([&] { return source.Read(out); }));
  temps->SetOk(false);
  ASSERT_TRUE(WaitFor([&] { return !source.Read(out); }));
  std::vector<hw::RawTemperature> sentinel(9, hw::RawTemperature{-999.0, false});
  EXPECT_FALSE(source.Read(sentinel));
  for (const auto& t : sentinel) EXPECT_EQ(t.temp_c, -999.0);
  temps->SetOk(true);
  ASSERT_TRUE(WaitFor([&] { return source.Read(out); }));
}

TEST_F(ServerClientTest, RangeChangeWrittenToTheModuleChangesTheScaling) {
  RawClient raw(port, 2);
  ASSERT_TRUE(raw.connected);
  EXPECT_EQ(modbus_write_register(raw.ctx, adam6015::kTypeCodeAddress + 0, 0x0099), -1);  // not a type code
  EXPECT_EQ(errno, EMBXILVAL);
  ASSERT_EQ(modbus_write_register(raw.ctx, adam6015::kTypeCodeAddress + 0, 0x21), 1);  // Pt100 0..100 °C
  temps->Set(0, 25.0);
  // 25 °C on 0..100 °C is a quarter of full scale.
  ASSERT_TRUE(WaitFor([&] {
    std::uint16_t v = 0;
    return modbus_read_registers(raw.ctx, adam6015::kAiValueAddress, 1, &v) == 1 && v == CelsiusToAdamRaw(25.0, *FindRtdRange(0x21));
  }));
  ModbusTemperatureSource source(TempOptions());  // reads type codes on connect
  std::vector<hw::RawTemperature> out(9);
  ASSERT_TRUE(source.Read(out)) << source.last_error();
  EXPECT_EQ(source.ChannelRange(0)->code, 0x21);
  EXPECT_EQ(source.ChannelRange(1)->code, adam6015::kDefaultRangeCode);
  EXPECT_NEAR(out[0].temp_c, 25.0, AdamResolutionC(*FindRtdRange(0x21)));
}

TEST_F(ServerClientTest, Adam6015RegistersBesidesTheValues) {
  RawClient raw(port, 2);
  ASSERT_TRUE(raw.connected);
  std::uint16_t name[2];
  ASSERT_EQ(modbus_read_registers(raw.ctx, adam6015::kModuleNameAddress, 2, name), 2);
  EXPECT_EQ(name[0], 0x6015);
  std::uint16_t enable = 0;
  ASSERT_EQ(modbus_read_registers(raw.ctx, adam6015::kChannelEnableAddress, 1, &enable), 1);
  EXPECT_EQ(enable, 0x7F);
  RawClient second(port, 3);  // the second module holds the last 2 channels
  ASSERT_EQ(modbus_read_registers(second.ctx, adam6015::kChannelEnableAddress, 1, &enable), 1);
  EXPECT_EQ(enable, 0x03);
  // FC 04 answers the same values as FC 03.
  std::uint16_t hr[7], ir[7];
  temps->Set(2, 40.0);
  ASSERT_TRUE(WaitFor([&] {
    return modbus_read_registers(raw.ctx, 0, 7, hr) == 7 && hr[2] == CelsiusToAdamRaw(40.0, *FindRtdRange(0x20));
  }));
  ASSERT_EQ(modbus_read_input_registers(raw.ctx, 0, 7, ir), 7);
  EXPECT_EQ(ir[2], hr[2]);
  // Historical max/min follow the readings; the reset coil brings them back to now.
  temps->Set(2, 60.0);
  ASSERT_TRUE(WaitFor([&] {
    std::uint16_t mx = 0;
    return modbus_read_registers(raw.ctx, adam6015::kAiMaxAddress + 2, 1, &mx) == 1 && mx == CelsiusToAdamRaw(60.0, *FindRtdRange(0x20));
  }));
  temps->Set(2, 45.0);
  std::uint16_t mn = 0;
  ASSERT_EQ(modbus_read_registers(raw.ctx, adam6015::kAiMinAddress + 2, 1, &mn), 1);
  EXPECT_LE(mn, CelsiusToAdamRaw(40.0, *FindRtdRange(0x20)));
  ASSERT_TRUE(WaitFor([&] {
    std::uint16_t v = 0;
    return modbus_read_registers(raw.ctx, 2, 1, &v) == 1 && v == CelsiusToAdamRaw(45.0, *FindRtdRange(0x20));
  }));
  ASSERT_EQ(modbus_write_bit(raw.ctx, adam6015::kResetMaxCoilAddress + 2, 1), 1);
  std::uint16_t mx = 0;
  ASSERT_EQ(modbus_read_registers(raw.ctx, adam6015::kAiMaxAddress + 2, 1, &mx), 1);
  EXPECT_EQ(mx, CelsiusToAdamRaw(45.0, *FindRtdRange(0x20)));
  std::uint8_t coil = 9;
  ASSERT_EQ(modbus_read_bits(raw.ctx, adam6015::kResetMaxCoilAddress + 2, 1, &coil), 1);
  EXPECT_EQ(coil, 0);  // reset coils read back 0
}

TEST_F(ServerClientTest, ReadOnlyRegistersUnknownUnitsAndFunctionsAreRefused) {
  RawClient pmc(port, 1);
  ASSERT_TRUE(pmc.connected);
  EXPECT_EQ(modbus_write_register(pmc.ctx, 1, 5), -1);  // reserved
  EXPECT_EQ(errno, EMBXILADD);
  const std::uint16_t across[3] = {1, 0, 0};
  EXPECT_EQ(modbus_write_registers(pmc.ctx, 0, 3, across), -1);  // enable + reserved
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_write_register(pmc.ctx, pmc::kHrEnable, 2), -1);  // a bit is 0 or 1
  EXPECT_EQ(errno, EMBXILVAL);
  EXPECT_EQ(modbus_write_register(pmc.ctx, pmc::CompensationRegister(3), 0), -1);  // only 3 axes
  EXPECT_EQ(errno, EMBXILADD);
  std::uint16_t too_far[4];
  EXPECT_EQ(modbus_read_input_registers(pmc.ctx, pmc::InputWindowLength(3), 4, too_far), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_mask_write_register(pmc.ctx, 0, 0, 1), -1);
  EXPECT_EQ(errno, EMBXILFUN);

  RawClient adam(port, 2);
  EXPECT_EQ(modbus_write_register(adam.ctx, adam6015::kAiValueAddress, 1000), -1);
  EXPECT_EQ(errno, EMBXILADD);
  EXPECT_EQ(modbus_write_bit(adam.ctx, adam6015::kBurnoutCoilAddress, 1), -1);
  EXPECT_EQ(errno, EMBXILADD);

  RawClient nobody(port, 42);
  std::uint16_t v;
  EXPECT_EQ(modbus_read_registers(nobody.ctx, 0, 1, &v), -1);
  EXPECT_EQ(errno, EMBXGTAR);
  // The refused requests changed nothing.
  std::uint16_t enable = 9;
  ASSERT_EQ(modbus_read_registers(pmc.ctx, pmc::kHrEnable, 1, &enable), 1);
  EXPECT_EQ(enable, 1);
  EXPECT_GE(server->Stats().exceptions, 8u);  // the read past the window is refused by libmodbus itself
}

TEST_F(ServerClientTest, GarbageOnOneConnectionDoesNotDisturbOthers) {
  ModbusCncLink link(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state); }));
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  const char junk[] = "GET / HTTP/1.1\r\nHost: x\r\n\r\n";
  ASSERT_GT(write(fd, junk, sizeof junk - 1), 0);
  const char half[] = {0x00, 0x01, 0x00, 0x00};  // a frame that stops after 4 bytes
  const int fd2 = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_EQ(connect(fd2, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_GT(write(fd2, half, sizeof half), 0);
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(link.Read(axes, state)) << i << " " << link.last_error();
  // The junk connection was dropped; the stalled one is still held, harmlessly.
  char byte;
  EXPECT_EQ(read(fd, &byte, 1), 0);
  EXPECT_TRUE(WaitFor([&] { return server->Stats().clients == 2; }));
  close(fd);
  close(fd2);
}

TEST_F(ServerClientTest, SeveralClientsAtOnce) {
  constexpr int kClients = 4;
  std::atomic<int> ok{0};
  std::vector<std::thread> threads;
  for (int k = 0; k < kClients; ++k) {
    threads.emplace_back([&, k] {
      ModbusCncLink link(LinkOptions());
      ModbusTemperatureSource source(TempOptions());
      std::vector<hw::AxisState> axes(3);
      hw::CncState state;
      std::vector<hw::RawTemperature> t(9);
      int good = 0;
      for (int i = 0; i < 100; ++i) good += link.Read(axes, state) && source.Read(t);
      if (k == 0) good = good && link.WriteCompensation(std::vector<double>{1.0, 2.0, 3.0}) ? good : -1;
      if (good == 100) ok.fetch_add(1);
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(ok.load(), kClients);
  EXPECT_GE(server->Stats().connections, 2u * kClients);
  ASSERT_TRUE(WaitFor([&] { return cnc->Compensation()[2] == 3.0; }));
}

TEST_F(ServerClientTest, StaleMachineSideIsALinkFaultEvenThoughTheServerAnswers) {
  auto o = LinkOptions();
  o.stale_after_s = 0.2;
  ModbusCncLink link(o);
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state); }));
  cnc->SetHang(true);  // the CNC stops answering its terminal: the machine thread is stuck in Read()
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  ASSERT_TRUE(WaitFor([&] { return !link.Read(axes, state); }, 3.0));
  EXPECT_TRUE(link.connected());  // the network side kept answering throughout
  cnc->SetHang(false);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state); }));
}

TEST_F(ServerClientTest, MachineReadFailureIsReportedAsALinkFault) {
  ModbusCncLink link(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state); }));
  cnc->SetReadOk(false);
  ASSERT_TRUE(WaitFor([&] { return !link.Read(axes, state); }));
  cnc->SetReadOk(true);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state); }));
}

TEST_F(ServerClientTest, LinkLossFailsPromptlyAndReconnectWorks) {
  ModbusCncLink link(LinkOptions());
  ModbusTemperatureSource source(TempOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  std::vector<hw::RawTemperature> t(9);
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && source.Read(t); }));
  server->Stop();
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(link.Read(axes, state));
  EXPECT_FALSE(link.WriteCompensation(std::vector<double>{1.0, 1.0, 1.0}));
  EXPECT_FALSE(source.Read(t));
  const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(took_s, 2.0);  // bounded by the response timeouts, not hanging
  EXPECT_FALSE(link.connected());
  // While down, calls keep failing (no hang) ...
  for (int i = 0; i < 5; ++i) EXPECT_FALSE(link.Read(axes, state));
  // ... and after the terminal comes back on the same port, the clients reconnect by themselves.
  options.port = port;
  server = std::make_unique<ModbusMachineServer>(cnc.get(), temps.get(), options);
  std::string error;
  ASSERT_TRUE(WaitFor([&] { return server->Start(&error); }, 5.0)) << error;
  ASSERT_TRUE(WaitFor([&] { return link.Read(axes, state) && source.Read(t); }, 5.0)) << link.last_error();
  EXPECT_GE(link.reconnects(), 2u);
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{7.0, 8.0, 9.0}));
  ASSERT_TRUE(WaitFor([&] { return cnc->Compensation()[2] == 9.0; }));
}

TEST_F(ServerClientTest, ClientRefusesAWindowWithAnotherAxisCount) {
  auto o = LinkOptions();
  o.axis_names = {"X", "Y"};
  ModbusCncLink link(o);
  std::vector<hw::AxisState> axes(2);
  hw::CncState state;
  EXPECT_FALSE(link.Read(axes, state));
  EXPECT_NE(link.last_error().find("expected layout 1 with 2 axes"), std::string::npos) << link.last_error();
}

TEST_F(ServerClientTest, TemperatureClientRefusesAUnitThatIsNotAnAdam) {
  auto o = TempOptions();
  o.unit_ids = {1, 3};  // unit 1 is the PMC window: it has no register 40211
  ModbusTemperatureSource source(o);
  std::vector<hw::RawTemperature> t(9);
  EXPECT_FALSE(source.Read(t));
  EXPECT_FALSE(source.last_error().empty());
}

TEST_F(ServerClientTest, ServerStopsWithClientsConnected) {
  ModbusCncLink a(LinkOptions()), b(LinkOptions());
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return a.Read(axes, state) && b.Read(axes, state); }));
  EXPECT_EQ(server->Stats().clients, 2);
  server->Stop();
  EXPECT_FALSE(server->running());
  server->Stop();  // idempotent
}

TEST(ModbusMachineServer, ANewClientAlwaysGetsInAndIdleOnesAreDropped) {
  MockCnc cnc({"X"});
  ModbusMachineServerOptions o;
  o.max_clients = 2;
  o.idle_timeout_s = 0.5;
  std::string error;
  auto server = StartServer(&cnc, nullptr, o, &error);
  ASSERT_NE(server, nullptr) << error;
  ModbusCncLinkOptions lo;
  lo.endpoint.port = server->options().port;
  lo.endpoint.response_timeout_s = kTestTimeoutS;
  lo.endpoint.reconnect_interval_s = 0.05;
  lo.axis_names = {"X"};
  ModbusCncLink a(lo), b(lo), c(lo);
  std::vector<hw::AxisState> axes(1);
  hw::CncState state;
  ASSERT_TRUE(a.Read(axes, state)) << a.last_error();
  ASSERT_TRUE(b.Read(axes, state)) << b.last_error();
  // Third connection while both slots are taken: it gets in, the longest-silent one (a) makes room.
  ASSERT_TRUE(c.Read(axes, state)) << c.last_error();
  EXPECT_TRUE(WaitFor([&] { return server->Stats().evicted_connections >= 1; }));
  // The others fall silent; after the idle timeout their slots are free again.
  ASSERT_TRUE(WaitFor([&] { return server->Stats().clients == 0; }, 5.0));
  EXPECT_GE(server->Stats().idle_disconnects, 2u);
  // A dropped client notices on its next call and reconnects by itself.
  ASSERT_TRUE(WaitFor([&] { return a.Read(axes, state); }, 3.0)) << a.last_error();
}

// Silent TCP connections (a port scanner, a crashed client's half-open sockets) filling every
// slot must not lock a real client out (16 of them used to, for the 60 s idle timeout).
TEST(ModbusMachineServer, SilentConnectionsFillingEverySlotDoNotLockClientsOut) {
  MockCnc cnc({"X"});
  std::string error;
  auto server = StartServer(&cnc, nullptr, {}, &error);
  ASSERT_NE(server, nullptr) << error;
  std::vector<int> silent;
  for (int i = 0; i < server->options().max_clients + 4; ++i) {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(server->options().port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ASSERT_EQ(connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    silent.push_back(fd);
  }
  ASSERT_TRUE(WaitFor([&] { return server->Stats().connections >= silent.size(); }));
  ModbusCncLinkOptions lo;
  lo.endpoint.port = server->options().port;
  lo.endpoint.response_timeout_s = kTestTimeoutS;
  lo.axis_names = {"X"};
  ModbusCncLink link(lo);
  std::vector<hw::AxisState> axes(1);
  hw::CncState state;
  EXPECT_TRUE(link.Read(axes, state)) << link.last_error();
  for (int fd : silent) close(fd);
}

TEST(ModbusMachineServer, NothingIsWrittenToTheCncBeforeAClientWrites) {
  MockCnc cnc({"X", "Y"});
  std::string error;
  auto server = StartServer(&cnc, nullptr, {}, &error);
  ASSERT_NE(server, nullptr) << error;
  ASSERT_TRUE(WaitFor([&] { return server->Stats().exchanges > 20; }));
  EXPECT_EQ(cnc.WriteAttempts(), 0);  // a restarted terminal must not zero a CNC's offsets (a jump)
}

TEST(ModbusMachineServer, ARefusingCncIsRetriedEachPeriodNotHammered) {
  MockCnc cnc({"X"});
  ModbusMachineServerOptions o;
  o.machine_period_s = 0.01;
  std::string error;
  auto server = StartServer(&cnc, nullptr, o, &error);
  ASSERT_NE(server, nullptr) << error;
  cnc.SetWriteOk(false);
  ModbusCncLinkOptions lo;
  lo.endpoint.port = server->options().port;
  lo.endpoint.response_timeout_s = kTestTimeoutS;
  lo.axis_names = {"X"};
  ModbusCncLink link(lo);
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{4.0}));  // the terminal accepted it
  std::vector<hw::AxisState> axes(1);
  hw::CncState state;
  ASSERT_TRUE(WaitFor([&] { return cnc.WriteAttempts() >= 3; }));
  const auto exchanges0 = server->Stats().exchanges;
  const int attempts0 = cnc.WriteAttempts();
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  const auto exchanges = server->Stats().exchanges - exchanges0;
  // At most one attempt per machine exchange (a busy loop would make thousands).
  EXPECT_LE(static_cast<std::uint64_t>(cnc.WriteAttempts() - attempts0), exchanges + 1);
  cnc.SetWriteOk(true);
  ASSERT_TRUE(WaitFor([&] { return cnc.Writes() == 1; }));
  EXPECT_EQ(cnc.Compensation()[0], 4.0);
}

TEST(ModbusMachineServer, WatchdogRampsAStaleCompensationToZeroWithoutAJump) {
  MockCnc cnc({"X", "Y"});
  cnc.record_history = true;
  ModbusMachineServerOptions o;
  o.watchdog_s = 0.2;
  o.watchdog_ramp_um_per_s = 100.0;
  std::string error;
  auto server = StartServer(&cnc, nullptr, o, &error);
  ASSERT_NE(server, nullptr) << error;
  ModbusCncLinkOptions lo;
  lo.endpoint.port = server->options().port;
  lo.endpoint.response_timeout_s = kTestTimeoutS;
  lo.axis_names = {"X", "Y"};
  ModbusCncLink link(lo);
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{50.0, -30.0}));
  ASSERT_TRUE(WaitFor([&] { return cnc.Compensation()[0] == 50.0; }));
  // The compensator falls silent: after 0.2 s the terminal ramps both axes to 0.
  ASSERT_TRUE(WaitFor([&] {
    auto c = cnc.Compensation();
    return c[0] == 0.0 && c[1] == 0.0;
  }, 5.0));
  const auto history = cnc.History();
  ASSERT_GT(history.size(), 5u);  // many small steps, not one
  for (std::size_t i = 1; i < history.size(); ++i)
    for (std::size_t a = 0; a < 2; ++a) EXPECT_LE(std::abs(history[i][a] - history[i - 1][a]), 25.0) << i;  // 50 → 0 in one go would be a jump
  EXPECT_GT(server->Stats().watchdog_steps, 5u);
  // A live compensator takes over again at once.
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{5.0, 5.0}));
  ASSERT_TRUE(WaitFor([&] { return cnc.Compensation()[1] == 5.0; }));
}

TEST(ModbusMachineServer, BadOptionsAndBusyPortsAreReported) {
  MockCnc cnc({"X"});
  ModbusMachineServerOptions o;
  std::string why;
  o.bind_address = "localhost-ish";
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("bind_address"), std::string::npos);
  o = {};
  o.rtd_range_code = 0x99;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("0x99"), std::string::npos);
  o = {};
  o.max_abs_compensation_um = -1;
  EXPECT_FALSE(o.IsValid(&why));

  std::string error;
  auto first = StartServer(&cnc, nullptr, {}, &error);
  ASSERT_NE(first, nullptr) << error;
  ModbusMachineServerOptions same;
  same.port = first->options().port;
  ModbusMachineServer second(&cnc, nullptr, same);
  EXPECT_FALSE(second.Start(&error));
  EXPECT_NE(error.find("cannot listen"), std::string::npos) << error;
  ModbusMachineServer none(nullptr, nullptr, {});
  EXPECT_FALSE(none.Start(&error));
  MockCnc wide({"A", "B", "C", "D", "E", "F", "G", "H", "I"});
  ModbusMachineServer too_many(&wide, nullptr, {});
  EXPECT_FALSE(too_many.Start(&error));
  EXPECT_NE(error.find("at most 8 axes"), std::string::npos) << error;
}

TEST(ModbusClients, InvalidOptionsFailWithoutTouchingTheNetwork) {
  ModbusCncLinkOptions o;
  o.endpoint.port = 0;
  ModbusCncLink link(o);
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  EXPECT_FALSE(link.Read(axes, state));
  EXPECT_NE(link.last_error().find("port 0"), std::string::npos) << link.last_error();
  ModbusTemperatureSourceOptions t;
  t.channel_names = std::vector<std::string>(8, "c");  // one module holds 7
  ModbusTemperatureSource source(t);
  std::vector<hw::RawTemperature> out(8);
  EXPECT_FALSE(source.Read(out));
  EXPECT_NE(source.last_error().find("hold only 7"), std::string::npos) << source.last_error();
}

TEST(ModbusClients, NobodyListeningFailsFastAndThrottlesRetries) {
  ModbusCncLinkOptions o;
  o.endpoint.port = 1;  // nothing listens on tcpmux
  o.endpoint.reconnect_interval_s = 10;
  ModbusCncLink link(o);
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  EXPECT_FALSE(link.Read(axes, state));
  EXPECT_NE(link.last_error().find("connect"), std::string::npos) << link.last_error();
  // Within the reconnect interval no new attempt is made: the error stays the first one.
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(link.Read(axes, state));
  EXPECT_EQ(link.reconnects(), 0u);
}

}  // namespace
}  // namespace trueaxis::drivers
