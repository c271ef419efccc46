#pragma once
// ShopMqttRelay: the workshop server's live values on an MQTT broker ([mqtt] in the shop file,
// docs/mqtt.md), for HMIs, dashboards or an MES beside the history. Every period, from one
// Shop::Snapshot(): per machine the status (the HTTP API's JSON) and one topic per axis and per
// temperature channel. A value that is not available is null with status "UNAVAILABLE", never the
// last number (MTConnect). Publishing never waits on the broker (MqttPublisher's own thread:
// last value per topic, retained, reconnect with backoff), so a broker that is down costs the
// shop nothing; its faults show in Stats().
#include <string>

#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/live/mqtt_publisher.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::live {

class ShopMqttRelay {
 public:
  // Throws InputError for options the publisher refuses (a shop name that is no topic level).
  ShopMqttRelay(const server::Shop& shop, const server::MqttConfig& config);
  ~ShopMqttRelay();  // Stop()

  void PublishOnce();  // one snapshot of every machine (the thread's step; tests call it directly)
  void Start();        // every config.period_s on its own thread (once: a stopped relay stays stopped)
  // Stops the thread, sends what is pending (bounded by the publisher's timeout), goes offline.
  void Stop();
  bool Flush(double timeout_s) { return publisher_.Flush(timeout_s); }
  MqttPublisherStats Stats() const { return publisher_.Stats(); }

 private:
  const server::Shop& shop_;
  server::MqttConfig config_;
  MqttPublisher publisher_;
  bool closed_ = false;
  core::PeriodicThread worker_;  // last: stopped first
};

}  // namespace trueaxis::live
