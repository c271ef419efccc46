#pragma once
// MqttPublisher: the workshop server's live values for other consumers (HMIs,
// dashboards, an MES) on an MQTT broker (Eclipse Paho C++, Debian
// libpaho-mqttpp-dev; broker e.g. Debian's mosquitto). Topics and payloads:
// docs/mqtt.md.
//
//   MqttPublisher mqtt({.broker = "tcp://127.0.0.1:1883", .shop = "hall3"});
//   mqtt.Publish("vmc01", status_json);              // trueaxis/hall3/vmc01/status
//   mqtt.PublishAt("vmc01", "axis/X", axis_json);    // trueaxis/hall3/vmc01/axis/X
//
// Never blocks the caller on the network: Publish() only hands the value to
// the publisher's thread. Every topic carries its LAST value (retained, QoS 1
// by default): a value not yet sent is replaced by a newer one for the same
// topic (counted as superseded — the topic's consumers only ever want the
// latest), so the queue holds at most one payload per topic and is bounded by
// max_pending_topics; a new topic beyond that is dropped and counted.
// When the broker goes away the thread reconnects with backoff; after each
// (re)connect it re-sends the last value of every topic, so a broker that
// restarted empty has every retained value back.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_map>

namespace trueaxis::live {

struct MqttPublisherOptions {
  std::string broker = "tcp://127.0.0.1:1883";  // tcp://host:port
  std::string client_id = "trueaxis-server";
  std::string topic_root = "trueaxis";
  std::string shop = "shop";                   // second topic level
  int qos = 1;                                 // 0, 1 or 2
  bool retain = true;
  std::size_t max_pending_topics = 4096;       // distinct topics waiting to be sent
  int max_in_flight = 1;                       // sent but not yet acknowledged (QoS >= 1); >1 is slower
                                               // on loopback (Paho sets no TCP_NODELAY: Nagle waits for
                                               // delayed ACKs), bench/results/shop_io.md
  double connect_timeout_s = 2.0;
  double publish_timeout_s = 2.0;              // a publish not acknowledged by then = link fault
  double reconnect_min_s = 0.1;                // backoff doubles from here ...
  double reconnect_max_s = 5.0;                // ... up to here
  int keepalive_s = 10;
  bool IsValid(std::string* why) const;
};

struct MqttPublisherStats {
  std::uint64_t accepted = 0;     // Publish calls taken
  std::uint64_t superseded = 0;   // values replaced by a newer one for the same topic before being sent
  std::uint64_t dropped = 0;      // refused: max_pending_topics new topics already waiting
  std::uint64_t invalid = 0;      // refused: a machine or subtopic that is not a valid topic level
  std::uint64_t published = 0;    // acknowledged by the broker (QoS >= 1) or handed to it (QoS 0)
  std::uint64_t republished = 0;  // last values re-sent after a reconnect (included in published)
  std::uint64_t connects = 0;     // successful connections (1 + reconnects)
  std::uint64_t link_faults = 0;  // failed connects and publishes
  std::size_t pending = 0;        // topics waiting now
  bool connected = false;
  std::string last_error;
  std::string BriefReport() const;
};

class MqttPublisher {
 public:
  // Starts the thread; does not wait for the broker (an absent broker is
  // retried in the background). Throws InputError for invalid options.
  explicit MqttPublisher(MqttPublisherOptions options);
  ~MqttPublisher();  // Close()
  MqttPublisher(const MqttPublisher&) = delete;
  MqttPublisher& operator=(const MqttPublisher&) = delete;

  // <root>/<shop>/<machine>/status. False when refused (see stats).
  bool Publish(std::string_view machine, std::string_view json_status);
  // <root>/<shop>/<machine>/<subtopic> (subtopic may have levels: "axis/X").
  bool PublishAt(std::string_view machine, std::string_view subtopic, std::string_view payload);

  // Waits until every accepted value is sent, or timeout_s passes (shutdown, tests). True when all sent.
  bool Flush(double timeout_s);
  // Sends what is pending (bounded by publish_timeout_s), marks the publisher
  // offline (<root>/<shop>/server/<client_id>/online = "offline"), disconnects,
  // stops the thread. Idempotent.
  void Close();

  MqttPublisherStats Stats() const;
  std::string Topic(std::string_view machine, std::string_view subtopic) const;
  std::string OnlineTopic() const;

 private:
  struct Client;
  void Run();
  bool ConnectOnce();
  bool Enqueue(std::string topic, std::string_view payload);
  void Backoff(double& wait_s);

  MqttPublisherOptions options_;
  std::unique_ptr<Client> client_;
  mutable std::mutex mu_;
  std::condition_variable wake_, progress_;
  std::unordered_map<std::string, std::string> pending_;  // topic -> latest payload not yet sent
  std::deque<std::string> order_;                         // pending topics, oldest first
  std::unordered_map<std::string, std::string> sent_;     // topic -> last payload sent (re-sent after a reconnect)
  std::size_t in_flight_ = 0;  // values handed to Paho, not yet acknowledged
  bool stop_ = false;
  MqttPublisherStats stats_;
  std::thread thread_;
};

}  // namespace trueaxis::live
