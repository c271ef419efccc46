// The terminal against independent MODBUS TCP peers Debian ships: mbpoll
// (C, libmodbus-free) and pymodbus 3.0 (Python). They know nothing of this
// project's code, only the register map in docs/protocols.md.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <regex>
#include <sstream>
#include <string>

#include "modbus_test_server.hpp"
#include "trueaxis/drivers/register_codec.hpp"

namespace trueaxis::drivers {
namespace {

using testing::MockCnc;
using testing::MockTemperatures;
using testing::StartServer;
using testing::WaitFor;

// Runs `command` (with a hard timeout) and returns its stdout; *status gets the exit status.
std::string RunCommand(const std::string& command, int* status) {
  std::string out;
  FILE* p = popen(("timeout 30 " + command + " 2>&1").c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  *status = pclose(p);
  return out;
}

// mbpoll prints "[ref]: \tvalue" per value.
std::map<int, long long> ParseMbpoll(const std::string& text) {
  std::map<int, long long> values;
  const std::regex line(R"(\[(\d+)\]:\s+(-?\d+))");
  for (std::sregex_iterator it(text.begin(), text.end(), line), end; it != end; ++it)
    values[std::stoi((*it)[1])] = std::stoll((*it)[2]);
  return values;
}

class PeersTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cnc = std::make_unique<MockCnc>(std::vector<std::string>{"X", "Y", "Z"});
    temps = std::make_unique<MockTemperatures>(7);
    cnc->SetAxis(0, {123.4567, +1, true});
    cnc->SetAxis(1, {-250.5, -1, false});
    cnc->SetState({CoolantState::kMist, true});
    temps->Set(0, 20.0);
    temps->Set(4, 31.5, /*fault=*/true);
    std::string error;
    server = StartServer(cnc.get(), temps.get(), {}, &error);
    ASSERT_NE(server, nullptr) << error;
    port = std::to_string(server->options().port);
    // Let the machine thread publish the state set above.
    ASSERT_TRUE(WaitFor([&] { return server->Stats().exchanges > 3; }));
  }
  std::string Mbpoll(const std::string& args) const { return "mbpoll -m tcp -1 -o 2 -p " + port + " " + args; }
  std::unique_ptr<MockCnc> cnc;
  std::unique_ptr<MockTemperatures> temps;
  std::unique_ptr<ModbusMachineServer> server;
  std::string port;
};

TEST_F(PeersTest, MbpollReadsThePmcWindowHeader) {
  int status = -1;
  const std::string out = RunCommand(Mbpoll("-a 1 -t 3 -r 1 -c 8 127.0.0.1"), &status);
  ASSERT_EQ(status, 0) << out;
  auto v = ParseMbpoll(out);
  EXPECT_EQ(v[1], 1) << out;  // layout version
  EXPECT_EQ(v[2], 3) << out;  // axes
  EXPECT_EQ(v[5], 2) << out;  // coolant: mist
  EXPECT_EQ(v[6] & 0x3, 0x3) << out;  // enabled, machine read OK
}

TEST_F(PeersTest, MbpollReadsPositionsAsBigEndianInt32InTenthsOfAMicrometre) {
  int status = -1;
  const std::string out = RunCommand(Mbpoll("-a 1 -t 3:int -B -r 17 -c 1 127.0.0.1"), &status);
  ASSERT_EQ(status, 0) << out;
  EXPECT_EQ(ParseMbpoll(out)[17], 1234567) << out;
  const std::string y = RunCommand(Mbpoll("-a 1 -t 3:int -B -r 25 -c 1 127.0.0.1"), &status);
  EXPECT_EQ(ParseMbpoll(y)[25], -2505000) << y;
  const std::string dir = RunCommand(Mbpoll("-a 1 -t 3 -r 27 -c 1 127.0.0.1"), &status);
  EXPECT_EQ(ParseMbpoll(dir)[27], 65535) << dir;  // int16 -1 shown unsigned
}

TEST_F(PeersTest, MbpollWritesACompensationThatReachesTheCnc) {
  int status = -1;
  const std::string out = RunCommand(Mbpoll("-a 1 -t 4:int -B -r 19 127.0.0.1 -- -123"), &status);  // axis Y, -12.3 µm
  ASSERT_EQ(status, 0) << out;
  ASSERT_TRUE(WaitFor([&] { return std::abs(cnc->Compensation()[1] + 12.3) < 1e-9; })) << out;
  EXPECT_EQ(cnc->Compensation()[0], 0.0);
  // Beyond the terminal's bound (1000 µm): refused, nothing changes.
  const std::string big = RunCommand(Mbpoll("-a 1 -t 4:int -B -r 17 127.0.0.1 20000"), &status);
  EXPECT_NE(status, 0) << big;
  EXPECT_EQ(cnc->Compensation()[0], 0.0);
}

TEST_F(PeersTest, MbpollReadsTheAdam6015ValuesAndBurnoutFlags) {
  int status = -1;
  const std::string out = RunCommand(Mbpoll("-a 2 -t 4 -r 1 -c 7 127.0.0.1"), &status);
  ASSERT_EQ(status, 0) << out;
  auto v = ParseMbpoll(out);
  const auto& range = *FindRtdRange(adam6015::kDefaultRangeCode);
  EXPECT_EQ(v[1], CelsiusToAdamRaw(20.0, range)) << out;
  EXPECT_EQ(v[2], CelsiusToAdamRaw(20.5, range)) << out;
  EXPECT_EQ(v[5], 65535) << out;  // burnt-out channel 4 reads full scale
  const std::string coils = RunCommand(Mbpoll("-a 2 -t 0 -r 121 -c 7 127.0.0.1"), &status);
  ASSERT_EQ(status, 0) << coils;
  auto b = ParseMbpoll(coils);
  EXPECT_EQ(b[125], 1) << coils;
  EXPECT_EQ(b[121], 0) << coils;
  const std::string codes = RunCommand(Mbpoll("-a 2 -t 4 -r 201 -c 7 127.0.0.1"), &status);
  EXPECT_EQ(ParseMbpoll(codes)[201], 0x20) << codes;
}

TEST_F(PeersTest, PymodbusReadsTheRegistersAndWritesACompensation) {
  int status = -1;
  const std::string script = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/drivers/peers/pymodbus_peer.py";
  const std::string out = RunCommand("/usr/bin/python3 " + script + " " + port + " 3 1.5 -2.5 300.0", &status);
  ASSERT_EQ(status, 0) << out;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(out.substr(out.find('{')))) << out;
  ASSERT_FALSE(j.contains("error")) << out;
  EXPECT_EQ(j["layout"], 1);
  EXPECT_EQ(j["axis_count"], 3);
  EXPECT_EQ(j["coolant"], 2);
  EXPECT_NEAR(j["position_mm"][0].get<double>(), 123.4567, 1e-9);
  EXPECT_NEAR(j["position_mm"][1].get<double>(), -250.5, 1e-9);
  EXPECT_EQ(j["direction"][1], -1);
  EXPECT_TRUE(j["write_ok"].get<bool>());
  EXPECT_EQ(j["adam_name"], 0x6015);
  EXPECT_EQ(j["adam_burnout"][4], 1);
  EXPECT_EQ(j["adam_burnout"][0], 0);
  EXPECT_EQ(j["adam_type_codes"][0], 0x20);
  EXPECT_NEAR(AdamRawToCelsius(j["adam_raw"][0].get<std::uint16_t>(), *FindRtdRange(0x20)), 20.0, 0.002);
  ASSERT_TRUE(WaitFor([&] { return std::abs(cnc->Compensation()[2] - 300.0) < 1e-9; })) << out;
  EXPECT_NEAR(cnc->Compensation()[0], 1.5, 1e-9);
  EXPECT_NEAR(cnc->Compensation()[1], -2.5, 1e-9);
}

}  // namespace
}  // namespace trueaxis::drivers
