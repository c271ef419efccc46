// Which optional features this build has (TRUEAXIS_HAVE_<NAME> 0/1, set for this file only by
// apps/trueaxis/CMakeLists.txt) and what each adds to the CLI. Without a feature its commands
// are still listed; they print that this build lacks it and how to get it, and exit 1.
#include "optional_features.hpp"

#include <CLI/CLI.hpp>

#include "command.hpp"
#include "trueaxis/core/feature_missing.hpp"

#if TRUEAXIS_HAVE_POSTGRES
#include "trueaxis/store_postgres/postgres_history_sink.hpp"
#endif
#if TRUEAXIS_HAVE_MQTT
#include "trueaxis/live/shop_mqtt.hpp"
#endif

namespace trueaxis::cli {
namespace {

// A command of a feature this build was configured without: any arguments, one answer.
void RegisterAbsentCommand(const char* name, const char* feature, const char* description) {
  CommandRegistrar(name, [=](CLI::App& app) {
    CLI::App* cmd = app.add_subcommand(name, std::string(description) + " (not in this build: needs " + feature + " support)");
    cmd->allow_extras();
    cmd->prefix_command();
    cmd->callback([feature] { throw FeatureMissing(feature); });
  });
}

[[maybe_unused]] const bool registered = [] {
#if TRUEAXIS_HAVE_POSTGRES
  store::EnablePostgresHistory();
#endif
#if !TRUEAXIS_HAVE_VISION
  RegisterAbsentCommand("vision", "vision", "Spindle growth read by a camera from a marker on the spindle");
  RegisterAbsentCommand("tool", "vision", "Tool thermal error: virtual tool, Tv from zones, heating/steady/cooling sub-models");
#endif
  return true;
}();

#if TRUEAXIS_HAVE_MQTT
class MqttRelay final : public LiveRelay {
 public:
  MqttRelay(const server::Shop& shop, const server::MqttConfig& config) : relay_(shop, config) {}
  void Start() override { relay_.Start(); }
  void Stop() override { relay_.Stop(); }
  std::string StatsReport() const override { return relay_.Stats().BriefReport(); }

 private:
  live::ShopMqttRelay relay_;
};
#endif

}  // namespace

std::unique_ptr<LiveRelay> MakeShopMqttRelay(const server::Shop& shop, const server::MqttConfig& config) {
#if TRUEAXIS_HAVE_MQTT
  return std::make_unique<MqttRelay>(shop, config);
#else
  throw FeatureMissing("MQTT");
#endif
}

}  // namespace trueaxis::cli
