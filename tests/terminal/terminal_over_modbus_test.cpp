// The terminal over real sockets on 127.0.0.1: DS18B20 readings from a fake
// 1-Wire tree served on the ADAM-6015 registers and read back with mbpoll (an
// independent MODBUS peer); a lost sensor reads as burn-out (0xFFFF + flag)
// and comes back; the CLI end to end; and a CNC relayed through the terminal
// whose compensation the watchdog ramps to zero when the server goes quiet.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <thread>

#include "drivers/modbus_test_server.hpp"
#include "fake_w1_tree.hpp"
#include "served_registers.hpp"
#include "support/cli_runner.hpp"
#include "support/local_process.hpp"
#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/register_codec.hpp"
#include "trueaxis/terminal/combined_temperature_source.hpp"
#include "trueaxis/terminal/one_wire_temperature_source.hpp"
#include "trueaxis/terminal/polled_temperature_source.hpp"

namespace trueaxis::terminal {
namespace {

using drivers::testing::StartServer;
using drivers::testing::WaitFor;
using testing::FakeW1Tree;
using testing::kA;
using testing::kB;

using testing::MbpollValues;
using testing::RawToC;

class TerminalOverModbus : public FakeW1Tree {
 protected:
  void SetUp() override {
    FakeW1Tree::SetUp();
    Set(kA, 23125);
    Set(kB, 31500);
    const OneWireOptions o = TwoSensors();
    std::vector<std::unique_ptr<hw::TemperatureSource>> parts;
    auto p = std::make_unique<PolledTemperatureSource>(std::make_unique<OneWireTemperatureSource>(o), 0.1, 1.0);
    polled = p.get();
    parts.push_back(std::move(p));
    temps = std::make_unique<CombinedTemperatureSource>(std::move(parts));
    std::string why;
    ASSERT_TRUE(hw::ConfigureAndActivate(*temps, &why)) << why;
    server = StartServer(nullptr, temps.get(), {}, &why);
    ASSERT_NE(server, nullptr) << why;
    port = std::to_string(server->options().port);
  }
  void TearDown() override {
    if (server) server->Stop();
    if (temps) temps->Deactivate();
    FakeW1Tree::TearDown();
  }
  // Waits until mbpoll reads `ok` for the first two AI registers of unit 2.
  template <class Pred>
  bool MbpollUntil(Pred ok, std::map<int, long long>* v, std::string* text) {
    return WaitFor([&] {
      text->clear();
      *v = MbpollValues(port, "-a 2 -t 4 -r 1 -c 2", text);
      return v->size() == 2 && ok(*v);
    }, 10.0);
  }
  std::unique_ptr<CombinedTemperatureSource> temps;
  PolledTemperatureSource* polled = nullptr;
  std::unique_ptr<drivers::ModbusMachineServer> server;
  std::string port;
};

TEST_F(TerminalOverModbus, MbpollReadsTheDs18b20TemperaturesAsAdam6015Channels) {
  std::map<int, long long> v;
  std::string text;
  ASSERT_TRUE(MbpollUntil([](auto& v) { return v[1] != 0 && v[2] != 0; }, &v, &text)) << text;
  EXPECT_NEAR(RawToC(v[1]), 23.125, 0.002) << text;  // 0.003 °C = one count of the −50…150 °C range
  EXPECT_NEAR(RawToC(v[2]), 31.5, 0.002) << text;
  std::string coils;
  auto flags = MbpollValues(port, "-a 2 -t 0 -r 121 -c 2", &coils);
  EXPECT_EQ(flags[121], 0) << coils;
  EXPECT_EQ(flags[122], 0) << coils;
}

TEST_F(TerminalOverModbus, LostSensorReadsAsBurnOutAndComesBack) {
  std::map<int, long long> v;
  std::string text;
  ASSERT_TRUE(MbpollUntil([](auto& v) { return v[2] != 0; }, &v, &text)) << text;
  Remove(kB);
  ASSERT_TRUE(MbpollUntil([](auto& v) { return v[2] == 65535; }, &v, &text)) << text;  // -21 decoded, 0xFFFF
  EXPECT_NEAR(RawToC(v[1]), 23.125, 0.002) << "the other sensor is unaffected\n" << text;
  std::string coils;
  auto flags = MbpollValues(port, "-a 2 -t 0 -r 121 -c 2", &coils);
  EXPECT_EQ(flags[122], 1) << coils;
  EXPECT_EQ(flags[121], 0) << coils;
  Set(kB, 29000);
  ASSERT_TRUE(MbpollUntil([](auto& v) { return v[2] != 65535; }, &v, &text)) << text;
  EXPECT_NEAR(RawToC(v[2]), 29.0, 0.002) << text;
}

TEST_F(TerminalOverModbus, PowerOnValueNeverReachesTheRegistersUnconfirmed) {
  std::map<int, long long> v;
  std::string text;
  ASSERT_TRUE(MbpollUntil([](auto& v) { return v[1] != 0; }, &v, &text)) << text;
  // A sensor that resets answers 85000 for one conversion, then a real value:
  // hold the file at 85000 for one poll (0.1 s period), then restore.
  for (int i = 0; i < 4; ++i) {
    const auto p0 = polled->polls();
    Set(kA, 85000);
    // One poll of the 85000 (the poll thread sleeps 0.1 s between reads of a few µs,
    // so the poll that completes next started after the write).
    ASSERT_TRUE(WaitFor([&] { return polled->polls() >= p0 + 1; }));
    std::string t;
    auto during = MbpollValues(port, "-a 2 -t 4 -r 1 -c 1", &t);
    Set(kA, 23125);
    ASSERT_EQ(during.size(), 1u) << t;
    EXPECT_TRUE(during[1] == 65535 || std::abs(RawToC(during[1]) - 23.125) < 0.002) << "served " << RawToC(during[1]) << " °C\n" << t;
    const auto p1 = polled->polls();
    ASSERT_TRUE(WaitFor([&] { return polled->polls() >= p1 + 2; }));
    t.clear();
    auto after = MbpollValues(port, "-a 2 -t 4 -r 1 -c 1", &t);
    EXPECT_NEAR(RawToC(after[1]), 23.125, 0.002) << t;
  }
}

TEST(TerminalCli, ServesAFakeTreeAndStopsByItself) {
  // The example tree of the README, on a port the test picks (a server probe first).
  std::string why;
  drivers::testing::MockTemperatures probe_temps(1);
  auto probe = StartServer(nullptr, &probe_temps, {}, &why);
  ASSERT_NE(probe, nullptr) << why;
  const int port = probe->options().port;
  probe->Stop();
  const std::string config = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/terminal/terminal.toml";
  std::thread reader([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    std::string text;
    const auto v = MbpollValues(std::to_string(port), "-a 2 -t 4 -r 1 -c 3", &text);
    EXPECT_EQ(v.size(), 3u) << text;
    if (v.size() == 3) {
      EXPECT_NEAR(RawToC(v.at(1)), 23.125, 0.002) << text;
      EXPECT_NEAR(RawToC(v.at(3)), 85.0, 0.002) << "confirmed by the second read\n" << text;
    }
  });
  const auto r = trueaxis::testing::RunCli("terminal --config " + config + " --port " + std::to_string(port) +
                                           " --duration-s 3 --status-interval-s 0 --json");
  reader.join();
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string out = r.output;
  while (!out.empty() && out.back() == '\n') out.pop_back();
  const auto j = nlohmann::json::parse(out.substr(out.rfind('\n') + 1));  // the last line: the final status
  EXPECT_EQ(j["kind"], "final");
  EXPECT_EQ(j["channels"][0]["name"], "x_nut");
  EXPECT_EQ(j["channels"][2]["power_on_refused"], 1) << "the first 85000 of 'bed' refused, the rest confirmed";
  EXPECT_EQ(j["channels"][2]["temp_c"], 85.0);
  EXPECT_GE(j["requests"].get<int>(), 1) << r.output;
}

TEST(TerminalCli, BadConfigNamesFileLineAndKey) {
  const std::string path = ::testing::TempDir() + "/bad_terminal.toml";
  std::ofstream(path) << "[cnc]\nkind = \"none\"\n\n[one_wire]\nroot = \"/tmp\"\n[[one_wire.sensor]]\nid = \"29-1234\"\nchannel = \"a\"\n";
  const auto r = trueaxis::testing::RunCli("terminal --config " + path + " --duration-s 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad_terminal.toml:7: field 'one_wire.sensor[0].id'"), std::string::npos) << r.output;
}

// The 1-Wire root: a file is refused; a directory that does not exist (the bus driver not loaded)
// is said out loud — it left every channel never_read without a word.
TEST(TerminalCli, AOneWireRootThatIsAFileIsRefusedAMissingOneWarned) {
  std::string why;
  drivers::testing::MockTemperatures probe_temps(1);
  auto probe = StartServer(nullptr, &probe_temps, {}, &why);  // a free port, as the test above
  ASSERT_NE(probe, nullptr) << why;
  const int port = probe->options().port;
  probe->Stop();
  const std::string dir = ::testing::TempDir();
  const std::string file = dir + "/w1_is_a_file";
  std::ofstream(file) << "x";
  const auto config = [&](const std::string& root) {
    const std::string path = dir + "/w1_root_terminal.toml";
    std::ofstream(path) << "[cnc]\nkind = \"none\"\n\n[serve]\nbind = \"127.0.0.1\"\nport = " << port << "\n\n[one_wire]\nroot = \"" << root
                        << "\"\n[[one_wire.sensor]]\nid = \"28-0316a2794aff\"\nchannel = \"a\"\n";
    return path;
  };
  auto r = trueaxis::testing::RunCli("terminal --config " + config(file) + " --duration-s 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("field 'one_wire.root'"), std::string::npos) << r.output;
  r = trueaxis::testing::RunCli("terminal --config " + config(dir + "/no_such_w1") + " --duration-s 0.5 --status-interval-s 0");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: the 1-Wire devices directory"), std::string::npos) << r.output;
}

// A CNC behind a MODBUS gateway (here a ModbusMachineServer over a fake CNC),
// relayed by the terminal: the server's compensation reaches the CNC, and when
// the server stops writing the terminal's watchdog ramps it to zero without a jump.
TEST(TerminalRelay, WatchdogRampsTheRelayedCompensationToZero) {
  drivers::testing::MockCnc cnc({"X", "Y"});
  cnc.record_history = true;  // every vector the CNC accepted, to check the ramp has no jump
  cnc.SetState({CoolantState::kOff, true});
  std::string why;
  auto gateway = StartServer(&cnc, nullptr, {}, &why);
  ASSERT_NE(gateway, nullptr) << why;
  drivers::ModbusCncLinkOptions lo;
  lo.endpoint.port = gateway->options().port;
  lo.axis_names = {"X", "Y"};
  drivers::ModbusCncLink relay(lo);
  ASSERT_TRUE(hw::ConfigureAndActivate(relay, &why)) << why;
  drivers::testing::MockTemperatures temps(1);
  drivers::ModbusMachineServerOptions to;
  to.watchdog_s = 0.3;
  to.watchdog_ramp_um_per_s = 100;
  to.machine_period_s = 0.01;
  auto terminal = StartServer(&relay, &temps, to, &why);
  ASSERT_NE(terminal, nullptr) << why;

  drivers::ModbusCncLinkOptions so;  // the workshop server's side
  so.endpoint.port = terminal->options().port;
  so.axis_names = {"X", "Y"};
  drivers::ModbusCncLink server_link(so);
  ASSERT_TRUE(hw::ConfigureAndActivate(server_link, &why)) << why;
  const std::vector<double> comp{12.0, -8.0};
  ASSERT_TRUE(server_link.WriteCompensation(comp));
  ASSERT_TRUE(WaitFor([&] { return cnc.Compensation() == comp; })) << "the CNC never received the relayed vector";
  // Server silent: within a few seconds the CNC's compensation is back at 0, in small steps.
  ASSERT_TRUE(WaitFor([&] { const auto c = cnc.Compensation(); return c[0] == 0 && c[1] == 0; }, 5.0));
  const auto history = cnc.History();
  double biggest_step = 0;
  for (std::size_t i = 1; i < history.size(); ++i)
    for (std::size_t a = 0; a < 2; ++a) biggest_step = std::max(biggest_step, std::abs(history[i][a] - history[i - 1][a]));
  EXPECT_GT(history.size(), 10u) << "ramped in steps, not one jump";
  EXPECT_LT(biggest_step, 5.0) << "largest step of the ramp (µm)";
  terminal->Stop();
  gateway->Stop();
}

}  // namespace
}  // namespace trueaxis::terminal
