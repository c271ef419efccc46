// MqttPublisher against a real mosquitto broker on 127.0.0.1, read by
// mosquitto_sub (an independent client): retained last values with the stated
// QoS, a broker killed mid-run (the caller keeps publishing, the publisher
// reconnects and restores every retained value), bounded queue with counted drops.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "mosquitto_broker.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/live/mqtt_publisher.hpp"

namespace trueaxis::live {
namespace {

template <class Pred>
bool WaitFor(Pred pred, double timeout_s = 10.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return pred();
}

MqttPublisherOptions OptionsFor(const testing::MosquittoBroker& broker) {
  MqttPublisherOptions o;
  o.broker = broker.Uri();
  o.shop = "hall3";
  o.client_id = "trueaxis-test";
  o.reconnect_min_s = 0.05;
  o.reconnect_max_s = 0.2;
  o.publish_timeout_s = 1.0;
  o.connect_timeout_s = 1.0;
  return o;
}

TEST(MqttPublisher, StatusIsRetainedWithQos1AndReadByMosquittoSub) {
  testing::MosquittoBroker broker;
  ASSERT_TRUE(broker.Start()) << broker.error();
  MqttPublisher mqtt(OptionsFor(broker));
  ASSERT_TRUE(mqtt.Publish("vmc01", R"({"connected":true,"corrections_um":{"X":-3.2}})"));
  ASSERT_TRUE(mqtt.PublishAt("vmc01", "axis/X", R"({"correction_um":-3.2})"));
  ASSERT_TRUE(mqtt.Flush(10)) << mqtt.Stats().BriefReport();
  // Subscribed after the publish: what arrives is the broker's retained copy (%r = 1).
  EXPECT_EQ(broker.Subscribe("trueaxis/hall3/vmc01/status"),
            R"(1 1 trueaxis/hall3/vmc01/status {"connected":true,"corrections_um":{"X":-3.2}})");
  EXPECT_EQ(broker.Subscribe("trueaxis/hall3/vmc01/axis/+"), R"(1 1 trueaxis/hall3/vmc01/axis/X {"correction_um":-3.2})");
  EXPECT_EQ(broker.Subscribe(mqtt.OnlineTopic()), "1 1 trueaxis/hall3/server/trueaxis-test/online online");
  mqtt.Close();
  EXPECT_EQ(broker.Subscribe(mqtt.OnlineTopic()), "1 1 trueaxis/hall3/server/trueaxis-test/online offline");
}

TEST(MqttPublisher, NewerValueOfATopicReplacesOneNotYetSent) {
  testing::MosquittoBroker broker;  // not started: nothing can be sent yet
  auto o = OptionsFor(broker);
  MqttPublisher mqtt(o);
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(mqtt.Publish("vmc01", "{\"n\":" + std::to_string(i) + "}"));
  auto s = mqtt.Stats();
  EXPECT_EQ(s.accepted, 100u);
  EXPECT_EQ(s.superseded, 99u);
  EXPECT_EQ(s.pending, 1u);
  ASSERT_TRUE(broker.Start()) << broker.error();
  ASSERT_TRUE(mqtt.Flush(10)) << mqtt.Stats().BriefReport();
  EXPECT_EQ(broker.Subscribe("trueaxis/hall3/vmc01/status"), R"(1 1 trueaxis/hall3/vmc01/status {"n":99})");
  EXPECT_EQ(mqtt.Stats().published, 1u);
}

TEST(MqttPublisher, BrokerKilledMidRunCallerKeepsGoingPublisherReconnectsAndRestoresRetained) {
  testing::MosquittoBroker broker;
  ASSERT_TRUE(broker.Start()) << broker.error();
  MqttPublisher mqtt(OptionsFor(broker));
  ASSERT_TRUE(mqtt.Publish("vmc01", R"({"t":1})"));
  ASSERT_TRUE(mqtt.Publish("lathe02", R"({"t":1})"));
  ASSERT_TRUE(mqtt.Flush(10)) << mqtt.Stats().BriefReport();
  ASSERT_EQ(mqtt.Stats().connects, 1u);

  broker.Kill();  // crash: no persistence, every retained value is gone with it
  for (int t = 2; t <= 50; ++t) {
    ASSERT_TRUE(mqtt.Publish("vmc01", "{\"t\":" + std::to_string(t) + "}"));  // never refused, never blocks on the dead link
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_TRUE(WaitFor([&] { return !mqtt.Stats().connected; })) << mqtt.Stats().BriefReport();
  EXPECT_GE(mqtt.Stats().pending, 1u);

  ASSERT_TRUE(broker.Start()) << broker.error();  // same port, empty broker
  ASSERT_TRUE(WaitFor([&] { return mqtt.Stats().connects >= 2 && mqtt.Stats().pending == 0; })) << mqtt.Stats().BriefReport();
  const auto s = mqtt.Stats();
  EXPECT_GE(s.link_faults, 1u) << s.BriefReport();
  EXPECT_GE(s.republished, 1u) << "lathe02's value was re-sent\n" << s.BriefReport();
  EXPECT_EQ(broker.Subscribe("trueaxis/hall3/vmc01/status"), R"(1 1 trueaxis/hall3/vmc01/status {"t":50})");
  EXPECT_EQ(broker.Subscribe("trueaxis/hall3/lathe02/status"), R"(1 1 trueaxis/hall3/lathe02/status {"t":1})");
}

TEST(MqttPublisher, QueueIsBoundedAndDropsAreCounted) {
  testing::MosquittoBroker broker;  // never started
  auto o = OptionsFor(broker);
  o.max_pending_topics = 3;
  MqttPublisher mqtt(o);
  for (const char* m : {"m1", "m2", "m3"}) EXPECT_TRUE(mqtt.Publish(m, "{}"));
  EXPECT_FALSE(mqtt.Publish("m4", "{}"));
  EXPECT_FALSE(mqtt.Publish("m5", "{}"));
  EXPECT_TRUE(mqtt.Publish("m2", "{\"newer\":1}"));  // a waiting topic is still updated
  const auto s = mqtt.Stats();
  EXPECT_EQ(s.dropped, 2u);
  EXPECT_EQ(s.pending, 3u);
  EXPECT_FALSE(s.connected);
  EXPECT_GE(s.link_faults, 0u);
}

TEST(MqttPublisher, RefusesNamesThatAreNotTopicLevels) {
  testing::MosquittoBroker broker;
  MqttPublisher mqtt(OptionsFor(broker));
  EXPECT_FALSE(mqtt.Publish("", "{}"));
  EXPECT_FALSE(mqtt.Publish("a/b", "{}"));
  EXPECT_FALSE(mqtt.Publish("vmc+", "{}"));
  EXPECT_FALSE(mqtt.Publish("#", "{}"));
  EXPECT_FALSE(mqtt.Publish("server", "{}"));  // reserved for the publisher's own online topic
  EXPECT_FALSE(mqtt.PublishAt("vmc01", "axis//X", "{}"));
  EXPECT_EQ(mqtt.Stats().invalid, 6u);
  auto o = OptionsFor(broker);
  o.shop = "hall/3";
  EXPECT_THROW(MqttPublisher bad(o), InputError);
  o = OptionsFor(broker);
  o.qos = 3;
  EXPECT_THROW(MqttPublisher bad(o), InputError);
}

}  // namespace
}  // namespace trueaxis::live
