// The shop file: errors name the file, the line and the field.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/shop_config.hpp"

namespace trueaxis::server {
namespace {

const char* kShop = R"(history = "shop.db"
[limits]
max_step_um = 0.5

[[machine]]
name = "mill-1"
host = "127.0.0.1"
port = 15001
axes = ["X", "Y"]
rtd_channels = ["x_nut", "ambient"]
model = "m.json"
period_s = 0.1
[machine.limits]
max_correction_um = 40
[[machine.axis]]
name = "Y"
pulse_equivalent_um = 0.5
)";

TEST(ShopConfig, ReadsMachinesWithShopDefaultsAndTheirOwnTables) {
  const ShopConfig c = ParseShopConfig(kShop, "/shops/a/shop.toml");
  EXPECT_EQ(c.history, "/shops/a/shop.db");
  EXPECT_EQ(c.audit_log, "/shops/a/shop.db.audit.jsonl");
  ASSERT_EQ(c.machines.size(), 1u);
  const MachineConfig& m = c.machines[0];
  EXPECT_EQ(m.model_file, "/shops/a/m.json");
  EXPECT_EQ(m.installation.compensator.shaper.max_step_um, 0.5);          // shop default
  EXPECT_EQ(m.installation.compensator.shaper.max_correction_um, 40);     // the machine's own
  ASSERT_EQ(m.axis_interfaces.size(), 2u);
  EXPECT_EQ(m.axis_interfaces[1].pulse_equivalent_um, 0.5);
  EXPECT_EQ(m.axis_interfaces[0].pulse_equivalent_um, 1.0);
  EXPECT_GE(m.installation.compensator.link_stale_after_s, 3 * m.period_s);
}

TEST(ShopConfig, APostgresHistoryIsKeptAsWrittenAndNeedsAnAuditFile) {
  std::string text = kShop;
  text.replace(text.find("\"shop.db\""), 9, "\"postgresql://shop@db:5432/shop\"\naudit_log = \"audit.jsonl\"");
  const ShopConfig c = ParseShopConfig(text, "/shops/a/shop.toml");
  EXPECT_EQ(c.history, "postgresql://shop@db:5432/shop");
  EXPECT_EQ(c.audit_log, "/shops/a/audit.jsonl");
  std::string without_audit = kShop;
  without_audit.replace(without_audit.find("\"shop.db\""), 9, "\"postgresql://shop@db:5432/shop\"");
  try {
    ParseShopConfig(without_audit, "shop.toml");
    FAIL() << "a PostgreSQL history without audit_log was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "audit_log") << e.what();
  }
}

void ExpectError(const std::string& text, int line, const std::string& field) {
  try {
    ParseShopConfig(text, "shop.toml");
    FAIL() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_EQ(e.source(), "shop.toml");
  }
}

TEST(ShopConfig, ErrorsNameLineAndField) {
  ExpectError(std::string(kShop) + "\n[[machine]]\nname = \"mill-1\"\naxes=[\"X\"]\nmodel=\"m.json\"\n", 20, "machine[1].name");
  struct Edit {
    const char* from;
    const char* to;
    int line;
    const char* field;
  };
  for (const Edit& e : {Edit{"port = 15001", "port = 99999", 8, "machine[0].port"},
                        Edit{"host = \"127.0.0.1\"", "host = \"mill.local\"", 7, "machine[0].host"},
                        Edit{"period_s = 0.1", "perod_s = 0.1", 12, "machine[0].perod_s"},
                        Edit{"name = \"Y\"", "name = \"W\"", 15, "machine[0].axis"}}) {
    std::string s = kShop;
    s.replace(s.find(e.from), std::string(e.from).size(), e.to);
    ExpectError(s, e.line, e.field);
  }
  ExpectError("history = \"x.db\"\n", 1, "machine");
}

// [server] poll_threads: 1 by default, 1 to kMaxPollThreads; anything else names its line.
TEST(ShopConfig, PollThreadsAreReadAndOutOfRangeIsRefused) {
  EXPECT_EQ(ParseShopConfig(kShop, "shop.toml").poll_threads, 1);
  auto with = [](const std::string& server) {
    std::string s = kShop;
    return s.insert(s.find("[limits]"), "[server]\n" + server + "\n");
  };
  EXPECT_EQ(ParseShopConfig(with("poll_threads = 2"), "shop.toml").poll_threads, 2);
  EXPECT_EQ(ParseShopConfig(with(fmt::format("poll_threads = {}", kMaxPollThreads)), "shop.toml").poll_threads, kMaxPollThreads);
  ExpectError(with("poll_threads = 0"), 3, "server.poll_threads");
  ExpectError(with(fmt::format("poll_threads = {}", kMaxPollThreads + 1)), 3, "server.poll_threads");
  ExpectError(with("poll_threads = 1.5"), 3, "server.poll_threads");
  ExpectError(with("pol_threads = 2"), 3, "server.pol_threads");
}

// A machine's temperature pipeline and data-driven thermal model, read as `run` reads them.
TEST(ShopConfig, AMachineHasItsOwnSignalTableAndThermalChannels) {
  std::string text = kShop;
  text.replace(text.find("[machine.limits]"), 16,
               "thermal_channels = { X = \"X_at_300mm\" }\n[machine.signal]\ncalibration = \"cal/mill-1.json\"\n"
               "groups = [[\"x_nut\", \"ambient\"]]\nmax_disagreement_c = 4\n[machine.limits]");
  const ShopConfig c = ParseShopConfig(text, "/shops/a/shop.toml");
  const station::InstallationConfig& r = c.machines.at(0).installation;
  EXPECT_TRUE(r.signal_processing);
  EXPECT_EQ(r.calibration_file, "/shops/a/cal/mill-1.json");  // relative to the shop file
  ASSERT_EQ(r.redundant_groups.size(), 1u);
  EXPECT_EQ(r.redundant_groups[0], (std::vector<std::string>{"x_nut", "ambient"}));
  EXPECT_EQ(r.compensator.sensor.judge.max_disagreement_c, 4);
  EXPECT_EQ(r.thermal_channels.at("X"), "X_at_300mm");
  EXPECT_EQ(r.model_file, "/shops/a/m.json");
  EXPECT_EQ(r.compensator.shaper.max_correction_um, 40);
  // Its errors name the machine's table, as `run`'s name [signal].
  std::string bad = kShop;
  bad.replace(bad.find("[machine.limits]"), 16, "[machine.signal]\nenabled = false\ncalibration = \"c.json\"\n[machine.limits]");
  ExpectError(bad, 15, "machine[0].signal.calibration");
}

// Sweep 2: two compensators on one terminal, temperatures read more often than the poll, an axis twice.
TEST(ShopConfig, RefusesASharedTerminalAFastTemperaturePeriodAndAnAxisTwice) {
  const std::string second = "\n[[machine]]\nname = \"mill-2\"\nhost = \"127.0.0.1\"\nport = 15001\naxes = [\"X\"]\nmodel = \"m.json\"\n";
  ExpectError(std::string(kShop) + second, 22, "machine[1].port");
  std::string other_port = std::string(kShop) + second;
  other_port.replace(other_port.rfind("15001"), 5, "15002");
  EXPECT_EQ(ParseShopConfig(other_port, "shop.toml").machines.size(), 2u);
  std::string s = kShop;
  s.replace(s.find("period_s = 0.1"), 14, "period_s = 0.1\ntemperature_period_s = 0.01");
  ExpectError(s, 13, "machine[0].temperature_period_s");
  s = kShop;
  s.replace(s.find("axes = [\"X\", \"Y\"]"), 17, "axes = [\"X\", \"X\"]");
  ExpectError(s, 9, "machine[0].axes");
  s = kShop;
  s.replace(s.find("rtd_channels = [\"x_nut\", \"ambient\"]"), 35, "rtd_channels = [\"x_nut\", \"x_nut\"]");
  ExpectError(s, 10, "machine[0].rtd_channels");  // one name for two inputs mixes two sensors
  // A slow poll with the default temperature period (1 s) is still accepted.
  s = kShop;
  s.replace(s.find("period_s = 0.1"), 14, "period_s = 2.0");
  EXPECT_EQ(ParseShopConfig(s, "shop.toml").machines[0].temperature_period_s, 2.0);
}

}  // namespace
}  // namespace trueaxis::server
