#include "trueaxis/live/shop_mqtt.hpp"

#include <cmath>

#include <nlohmann/json.hpp>

#include "trueaxis/server/http_api.hpp"

namespace trueaxis::live {

using server::MachineStatus;
using server::ToJson;

namespace {
MqttPublisherOptions PublisherOptions(const server::MqttConfig& c) {
  MqttPublisherOptions o;
  o.broker = c.broker;
  o.shop = c.shop;
  o.topic_root = c.topic_root;
  o.client_id = c.client_id;
  o.qos = c.qos;
  return o;
}

nlohmann::json ValueWithStatus(const std::optional<double>& value, const char* key) {
  return value ? nlohmann::json{{key, *value}, {"status", "ok"}} : nlohmann::json{{key, nullptr}, {"status", "UNAVAILABLE"}};
}
}  // namespace

ShopMqttRelay::ShopMqttRelay(const server::Shop& shop, const server::MqttConfig& config)
    : shop_(shop), config_(config), publisher_(PublisherOptions(config)) {}

ShopMqttRelay::~ShopMqttRelay() { Stop(); }

void ShopMqttRelay::PublishOnce() {
  for (const MachineStatus& m : shop_.Snapshot()) {
    publisher_.Publish(m.name, ToJson(m).dump());
    for (const auto& a : m.axes) {
      nlohmann::json j = ValueWithStatus(m.connected ? a.position_mm : std::nullopt, "position_mm");
      j["correction_um"] = m.connected && std::isfinite(a.output_um) ? nlohmann::json(a.output_um) : nlohmann::json(nullptr);
      j["applied_um"] = a.applied_um ? nlohmann::json(*a.applied_um) : nlohmann::json(nullptr);
      j["enabled"] = a.enabled;
      j["state"] = a.state;  // full | fallback_model | geometric | disabled | link_lost
      publisher_.PublishAt(m.name, "axis/" + a.name, j.dump());
    }
    for (const auto& c : m.channels) {
      nlohmann::json j = ValueWithStatus(c.temp_c, "temp_c");
      if (c.temp_c) j["status"] = c.health;  // ok | held | lost: the compensator's verdict
      publisher_.PublishAt(m.name, "temperature/" + c.name, j.dump());
    }
  }
}

void ShopMqttRelay::Start() {
  if (!closed_ && !worker_.Running()) worker_.Start(config_.period_s, [this](double) { PublishOnce(); });
}

void ShopMqttRelay::Stop() {
  worker_.Stop();
  publisher_.Close();
  closed_ = true;
}

}  // namespace trueaxis::live
