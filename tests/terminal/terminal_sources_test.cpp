// A terminal built from its TOML: DS18B20 sensors on a fake 1-Wire tree plus
// an RTD module reached over MODBUS TCP (here a ModbusMachineServer serving
// fake RTD channels, as an ADAM-6015 would), served together by the terminal
// and read with mbpoll; the RTD module going away faults only its channels.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "drivers/modbus_test_server.hpp"
#include "fake_w1_tree.hpp"
#include "served_registers.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/register_codec.hpp"
#include "trueaxis/terminal/terminal_sources.hpp"

namespace trueaxis::terminal {
namespace {

using drivers::testing::StartServer;
using drivers::testing::WaitFor;
using testing::kA;
using testing::kB;

class TerminalSourcesTest : public testing::FakeW1Tree {};

// The first `count` AI registers of unit 2 in °C (NaN for burn-out 0xFFFF); empty when mbpoll failed.
std::vector<double> ServedCelsius(int port, int count) {
  std::string text;
  const auto raw = testing::MbpollValues(std::to_string(port), fmt::format("-a 2 -t 4 -r 1 -c {}", count), &text);
  std::vector<double> v;
  for (int r = 1; r <= count; ++r) {
    if (!raw.count(r)) return {};
    v.push_back(raw.at(r) == 65535 ? std::nan("") : testing::RawToC(raw.at(r)));
  }
  return v;
}

TEST_F(TerminalSourcesTest, OneWireAndRtdServedTogetherAndARtdLossFaultsOnlyItsChannels) {
  Set(kA, 22500);
  // The "ADAM-6015" on the shop network: two RTD channels at 20.0 and 20.5 °C.
  drivers::testing::MockTemperatures rtd_values(2);
  std::string why;
  auto adam = StartServer(nullptr, &rtd_values, {}, &why);
  ASSERT_NE(adam, nullptr) << why;
  const std::string toml = fmt::format(R"(
[serve]
port = 1502
[one_wire]
root = "{}"
poll_period_s = 0.05
stale_after_s = 1
[[one_wire.sensor]]
id = "{}"
channel = "x_nut"
[[rtd]]
host = "127.0.0.1"
port = {}
unit_ids = [2]
channels = ["spindle_front", "spindle_rear"]
poll_period_s = 0.05
stale_after_s = 0.5
response_timeout_s = 0.2
[cnc]
kind = "none"
)", root(), kA, adam->options().port);
  const TerminalConfig cfg = ParseTerminalConfig(toml, "terminal.toml");
  EXPECT_EQ(cfg.ChannelNames(), (std::vector<std::string>{"x_nut", "spindle_front", "spindle_rear"}));
  TerminalSources sources = BuildTerminalSources(cfg);
  ASSERT_TRUE(hw::ConfigureAndActivate(*sources.combined, &why)) << why;
  auto terminal = StartServer(nullptr, sources.combined.get(), cfg.server, &why);
  ASSERT_NE(terminal, nullptr) << why;
  const int port = terminal->options().port;

  std::vector<double> v;
  ASSERT_TRUE(WaitFor([&] { v = ServedCelsius(port, 3); return v.size() == 3 && v[0] > 22 && v[1] > 19; }, 10.0));
  EXPECT_NEAR(v[0], 22.5, 0.002);
  EXPECT_NEAR(v[1], 20.0, 0.002);
  EXPECT_NEAR(v[2], 20.5, 0.002);

  adam->Stop();  // the RTD module is gone: its two channels become burn-out, the DS18B20 stays
  ASSERT_TRUE(WaitFor([&] { v = ServedCelsius(port, 3); return v.size() == 3 && std::isnan(v[1]); }, 10.0));
  EXPECT_NEAR(v[0], 22.5, 0.002);
  EXPECT_TRUE(std::isnan(v[2]));
  terminal->Stop();
  sources.combined->Deactivate();
}

TEST(TerminalConfigFile, OneWireStalenessGrowsWithTheSensorsUnlessGiven) {
  std::string toml = "[cnc]\nkind = \"none\"\n[one_wire]\n";
  for (int i = 0; i < 8; ++i) toml += fmt::format("[[one_wire.sensor]]\nid = \"28-00000000000{}\"\nchannel = \"c{}\"\n", i, i);
  EXPECT_DOUBLE_EQ(ParseTerminalConfig(toml, "t.toml").one_wire.poll.stale_after_s, 8 * 1.5 + 2 * 1.0);  // 8 conversions, twice
  const std::string given = "[cnc]\nkind = \"none\"\n[one_wire]\nstale_after_s = 3\n[[one_wire.sensor]]\nid = \"28-000000000001\"\nchannel = \"a\"\n";
  EXPECT_DOUBLE_EQ(ParseTerminalConfig(given, "t.toml").one_wire.poll.stale_after_s, 3.0);
}

TEST(TerminalConfigFile, ErrorsNameTheKey) {
  auto error_of = [](const std::string& toml) {
    try {
      ParseTerminalConfig(toml, "t.toml");
      return std::string();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(error_of("[one_wire]\n[[one_wire.sensor]]\nid = \"28-0316a2794aff\"\nchannel = \"a\"\n").find("'cnc'"), std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"none\"\n").find("no temperature channel"), std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"fanuc\"\n").find("cnc.kind"), std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"modbus\"\naxes = [\"X\"]\n[[rtd]]\nhost = \"h\"\nchannels = [\"a\"]\n").find("cnc.host"), std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"none\"\n[[rtd]]\nhost = \"h\"\nchannels = [\"a\", \"b\", \"c\", \"d\", \"e\", \"f\", \"g\", \"h\"]\n")
                .find("rtd[0].channels"),
            std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"none\"\n[[rtd]]\nhost = \"h\"\nchannels = [\"a\"]\n[[rtd]]\nhost = \"i\"\nchannels = [\"a\"]\n")
                .find("named twice"),
            std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"none\"\n[one_wire]\npoll_period_s = 2\nstale_after_s = 1\n[[one_wire.sensor]]\nid = \"28-0316a2794aff\"\nchannel = \"a\"\n")
                .find("one_wire.stale_after_s"),
            std::string::npos);
  EXPECT_NE(error_of("[cnc]\nkind = \"none\"\n[serve]\nprot = 1\n").find("serve.prot"), std::string::npos);
}

// [cnc] axes = ["X", "X", "Z"] was accepted (one axis would get two corrections); a repeated name in
// an [[rtd]] group was reported at line 1. Both now fail at the repeated element's line.
TEST(TerminalConfigFile, RepeatedAxisOrChannelFailsAtItsLine) {
  auto error_of = [](const std::string& toml) -> InputError {
    try {
      ParseTerminalConfig(toml, "t.toml");
    } catch (const InputError& e) {
      return e;
    }
    return InputError("accepted", "");
  };
  const InputError axes = error_of("[cnc]\nkind = \"modbus\"\nhost = \"127.0.0.1\"\naxes = [\"X\",\n  \"X\", \"Z\"]\n"
                                   "[[rtd]]\nhost = \"h\"\nchannels = [\"a\"]\n");
  EXPECT_EQ(axes.source(), "t.toml") << axes.what();
  EXPECT_EQ(axes.line(), 5) << axes.what();
  EXPECT_EQ(axes.field(), "cnc.axes") << axes.what();
  const InputError channels = error_of("[cnc]\nkind = \"none\"\n[[rtd]]\nhost = \"h\"\nchannels = [\"a\", \"b\", \"a\"]\n");
  EXPECT_EQ(channels.line(), 5) << channels.what();
  EXPECT_EQ(channels.field(), "rtd[0].channels") << channels.what();
  EXPECT_NE(std::string(channels.what()).find("channel 'a' is listed twice"), std::string::npos) << channels.what();
}

}  // namespace
}  // namespace trueaxis::terminal
