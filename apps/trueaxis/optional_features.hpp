#pragma once
// The optional features of this build (cmake/TrueaxisDeps.cmake, docs/building.md) as the CLI
// sees them: optional_features.cpp is the one file that knows which are built. A feature left
// out keeps its commands, which answer FeatureMissing (exit 1) instead of "unknown command".
#include <memory>
#include <string>

#include "trueaxis/server/shop.hpp"
#include "trueaxis/server/shop_config.hpp"

namespace trueaxis::cli {

// The workshop server's live values on MQTT ([mqtt] in the shop file).
class LiveRelay {
 public:
  virtual ~LiveRelay() = default;
  virtual void Start() = 0;
  virtual void Stop() = 0;  // sends what is pending, goes offline
  virtual std::string StatsReport() const = 0;
};

// Throws InputError for options the publisher refuses, FeatureMissing in a build without MQTT.
std::unique_ptr<LiveRelay> MakeShopMqttRelay(const server::Shop& shop, const server::MqttConfig& config);

}  // namespace trueaxis::cli
