// The workshop server's live values on a real mosquitto broker, read by mosquitto_sub (an
// independent client): every machine's status, axes and temperatures, retained; a lost terminal's
// values become null / UNAVAILABLE, never its last numbers.
#include "trueaxis/live/shop_mqtt.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mosquitto_broker.hpp"
#include "server/shop_fixture.hpp"
#include "trueaxis/core/input_error.hpp"

namespace trueaxis::server {
namespace {

using live::ShopMqttRelay;

using testing::ConfigFor;
using testing::StartVirtualShop;
using testing::TempDir;
using testing::WaitFor;
using testing::WaitUntilEveryMachineReads;
using testing::WriteModel;

// The payload of "%r %q %t %p" (retained, QoS, topic, payload).
nlohmann::json Payload(const std::string& line, std::string* topic = nullptr) {
  const auto t0 = line.find(' ', line.find(' ') + 1) + 1;
  const auto p0 = line.find(' ', t0) + 1;
  if (topic) *topic = line.substr(t0, p0 - 1 - t0);
  return nlohmann::json::parse(line.substr(p0));
}

TEST(ShopMqtt, EveryMachineIsPublishedAndALostTerminalBecomesUnavailable) {
  trueaxis::testing::MosquittoBroker broker;
  ASSERT_TRUE(broker.Start()) << broker.error();
  const std::string dir = TempDir("mqtt");
  auto vshop = StartVirtualShop(2);
  ASSERT_TRUE(vshop);
  ShopConfig config = ConfigFor(*vshop, WriteModel(dir + "/model.json"));
  config.mqtt.broker = "tcp://127.0.0.1:" + std::to_string(broker.port());
  config.mqtt.shop = "hall3";
  Shop shop(config, nullptr);
  shop.Start();
  ASSERT_TRUE(WaitUntilEveryMachineReads(shop));
  // Compensating with the model's own sensors (the CNC's enable comes a few cycles after the first read).
  ASSERT_TRUE(WaitFor([&] { return shop.Machine(config.machines[0].name)->axes[0].state == "full"; }));
  ShopMqttRelay relay(shop, config.mqtt);
  relay.PublishOnce();
  ASSERT_TRUE(relay.Flush(10)) << relay.Stats().BriefReport();

  const std::string m0 = config.machines[0].name, m1 = config.machines[1].name;
  const nlohmann::json status = Payload(broker.Subscribe("trueaxis/hall3/" + m1 + "/status"));
  EXPECT_EQ(status["name"], m1);
  EXPECT_EQ(status["connected"], true);
  const std::string axis = config.machines[0].axes[0], channel = config.machines[0].channels[0];
  std::string topic;
  const nlohmann::json a = Payload(broker.Subscribe("trueaxis/hall3/" + m0 + "/axis/" + axis), &topic);
  EXPECT_EQ(topic, "trueaxis/hall3/" + m0 + "/axis/" + axis);
  EXPECT_TRUE(a["position_mm"].is_number());
  EXPECT_TRUE(a["correction_um"].is_number());
  EXPECT_EQ(a["state"], "full");
  const nlohmann::json t = Payload(broker.Subscribe("trueaxis/hall3/" + m0 + "/temperature/" + channel));
  ASSERT_TRUE(t["temp_c"].is_number());
  EXPECT_GT(t["temp_c"].get<double>(), 5);
  EXPECT_LT(t["temp_c"].get<double>(), 60);

  vshop->SetFault(0, sim::TerminalFault::kDown);
  ASSERT_TRUE(WaitFor([&] { return !shop.Machine(m0)->connected; }));
  relay.PublishOnce();
  ASSERT_TRUE(relay.Flush(10)) << relay.Stats().BriefReport();
  const nlohmann::json lost_t = Payload(broker.Subscribe("trueaxis/hall3/" + m0 + "/temperature/" + channel));
  EXPECT_TRUE(lost_t["temp_c"].is_null()) << lost_t.dump();
  EXPECT_EQ(lost_t["status"], "UNAVAILABLE");
  const nlohmann::json lost_a = Payload(broker.Subscribe("trueaxis/hall3/" + m0 + "/axis/" + axis));
  EXPECT_TRUE(lost_a["position_mm"].is_null()) << lost_a.dump();
  EXPECT_EQ(Payload(broker.Subscribe("trueaxis/hall3/" + m0 + "/status"))["connected"], false);
  // the other machine is still published with numbers
  EXPECT_TRUE(Payload(broker.Subscribe("trueaxis/hall3/" + m1 + "/temperature/" + channel))["temp_c"].is_number());
  shop.Stop();
  vshop->Stop();
}

TEST(ShopMqtt, TheShopFileNamesTheBrokerOrIsRefused) {
  const std::string machine = R"(
[[machine]]
name = "m1"
axes = ["X"]
model = "m.json"
)";
  const ShopConfig c = ParseShopConfig("[mqtt]\nbroker = \"tcp://10.0.0.5:1883\"\nshop = \"hall3\"\nperiod_s = 2\n" + machine,
                                       "shop.toml");
  EXPECT_EQ(c.mqtt.broker, "tcp://10.0.0.5:1883");
  EXPECT_EQ(c.mqtt.shop, "hall3");
  EXPECT_EQ(c.mqtt.period_s, 2);
  for (const std::string& bad : {std::string("[mqtt]\nshop = \"x\"\n"), std::string("[mqtt]\nbroker = \"10.0.0.5\"\n"),
                                 std::string("[mqtt]\nbroker = \"tcp://a:1\"\nqos = 3\n"),
                                 std::string("[mqtt]\nbroker = \"tcp://a:1\"\ntopic = \"x\"\n")}) {
    try {
      ParseShopConfig(bad + machine, "shop.toml");
      FAIL() << "accepted: " << bad;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.field()).find("mqtt"), std::string::npos) << e.what();
      EXPECT_GT(e.line(), 0) << e.what();
    }
  }
}

}  // namespace
}  // namespace trueaxis::server
