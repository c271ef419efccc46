#include "trueaxis/live/mqtt_publisher.hpp"

#include <algorithm>
#include <chrono>
#include <vector>

#include <fmt/format.h>
#include <mqtt/async_client.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::live {
namespace {

// Paho's token::wait_for takes whole milliseconds.
long Ms(double seconds) { return std::max(1L, static_cast<long>(seconds * 1000.0 + 0.5)); }

// A topic level we build from a name: non-empty, no wildcard, no separator, no NUL, not "$…".
bool ValidLevel(std::string_view s) {
  return !s.empty() && s.front() != '$' && s.find_first_of(std::string_view("/+#\0", 4)) == std::string_view::npos;
}
// Levels separated by '/', each valid.
bool ValidLevels(std::string_view s) {
  std::size_t start = 0;
  for (;;) {
    const std::size_t slash = s.find('/', start);
    if (!ValidLevel(s.substr(start, slash == std::string_view::npos ? std::string_view::npos : slash - start))) return false;
    if (slash == std::string_view::npos) return true;
    start = slash + 1;
  }
}

}  // namespace

struct MqttPublisher::Client {
  explicit Client(const MqttPublisherOptions& o) : client(o.broker, o.client_id, static_cast<mqtt::iclient_persistence*>(nullptr)) {}
  mqtt::async_client client;
};

bool MqttPublisherOptions::IsValid(std::string* why) const {
  auto fail = [&](std::string msg) {
    if (why) *why = std::move(msg);
    return false;
  };
  if (broker.rfind("tcp://", 0) != 0 && broker.rfind("mqtt://", 0) != 0)
    return fail(fmt::format("broker '{}' must be tcp://host:port", broker));
  if (client_id.empty()) return fail("client_id is empty");
  if (!ValidLevels(topic_root)) return fail(fmt::format("topic_root '{}' is not a valid topic (no + # or empty levels)", topic_root));
  if (!ValidLevel(shop)) return fail(fmt::format("shop '{}' is not a valid topic level (no / + # $)", shop));
  if (!ValidLevel(client_id)) return fail(fmt::format("client_id '{}' is not a valid topic level (no / + # $)", client_id));
  if (qos < 0 || qos > 2) return fail(fmt::format("qos {} is not 0, 1 or 2", qos));
  if (max_pending_topics < 1) return fail("max_pending_topics must be >= 1");
  if (max_in_flight < 1 || max_in_flight > 65535) return fail("max_in_flight must be in 1..65535");
  if (!(connect_timeout_s > 0) || !(publish_timeout_s > 0)) return fail("timeouts must be > 0");
  if (!(reconnect_min_s > 0 && reconnect_max_s >= reconnect_min_s)) return fail("need 0 < reconnect_min_s <= reconnect_max_s");
  if (keepalive_s < 1) return fail("keepalive_s must be >= 1");
  return true;
}

std::string MqttPublisherStats::BriefReport() const {
  return fmt::format("{} ({} connects, {} link faults): {} accepted, {} published ({} re-sent after reconnects), {} superseded "
                     "by a newer value, {} dropped (queue full), {} invalid, {} pending{}",
                     connected ? "connected" : "not connected", connects, link_faults, accepted, published, republished, superseded,
                     dropped, invalid, pending, last_error.empty() ? "" : "; last error: " + last_error);
}

MqttPublisher::MqttPublisher(MqttPublisherOptions options) : options_(std::move(options)) {
  std::string why;
  if (!options_.IsValid(&why)) throw InputError("mqtt", 0, "options", why);
  try {
    client_ = std::make_unique<Client>(options_);
  } catch (const std::exception& e) {
    throw InputError("mqtt", 0, "broker", fmt::format("'{}': {}", options_.broker, e.what()));
  }
  thread_ = std::thread([this] { Run(); });
}

MqttPublisher::~MqttPublisher() { Close(); }

std::string MqttPublisher::Topic(std::string_view machine, std::string_view subtopic) const {
  return fmt::format("{}/{}/{}/{}", options_.topic_root, options_.shop, machine, subtopic);
}

std::string MqttPublisher::OnlineTopic() const {
  return fmt::format("{}/{}/server/{}/online", options_.topic_root, options_.shop, options_.client_id);
}

bool MqttPublisher::Publish(std::string_view machine, std::string_view json_status) { return PublishAt(machine, "status", json_status); }

bool MqttPublisher::PublishAt(std::string_view machine, std::string_view subtopic, std::string_view payload) {
  if (!ValidLevel(machine) || machine == "server" || !ValidLevels(subtopic)) {
    std::lock_guard<std::mutex> lock(mu_);
    ++stats_.invalid;
    return false;
  }
  return Enqueue(Topic(machine, subtopic), payload);
}

bool MqttPublisher::Enqueue(std::string topic, std::string_view payload) {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stop_) return false;
    auto it = pending_.find(topic);
    if (it != pending_.end()) {
      it->second.assign(payload);
      ++stats_.superseded;
    } else if (pending_.size() >= options_.max_pending_topics) {
      ++stats_.dropped;
      return false;
    } else {
      order_.push_back(topic);
      pending_.emplace(std::move(topic), std::string(payload));
    }
    ++stats_.accepted;
  }
  wake_.notify_one();
  return true;
}

MqttPublisherStats MqttPublisher::Stats() const {
  std::lock_guard<std::mutex> lock(mu_);
  MqttPublisherStats s = stats_;
  s.pending = pending_.size() + in_flight_;
  return s;
}

bool MqttPublisher::Flush(double timeout_s) {
  std::unique_lock<std::mutex> lock(mu_);
  return progress_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return pending_.empty() && in_flight_ == 0; });
}

void MqttPublisher::Backoff(double& wait_s) {
  std::unique_lock<std::mutex> lock(mu_);
  wake_.wait_for(lock, std::chrono::duration<double>(wait_s), [&] { return stop_; });
  wait_s = std::min(options_.reconnect_max_s, wait_s * 2);
}

bool MqttPublisher::ConnectOnce() {
  mqtt::connect_options co;
  co.set_clean_session(true);
  co.set_keep_alive_interval(options_.keepalive_s);
  co.set_connect_timeout(std::max(1, static_cast<int>(options_.connect_timeout_s + 0.5)));
  co.set_max_inflight(options_.max_in_flight);
  co.set_automatic_reconnect(false);  // ours: with backoff, and the retained values re-sent
  const std::string offline = "offline", online = "online";
  // A fresh client for every attempt: Paho's state after a lost link (a connect
  // or publish token still pending) must not leak into the next try.
  try {
    client_.reset();
    client_ = std::make_unique<Client>(options_);
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mu_);
    stats_.last_error = std::string("client: ") + e.what();
    ++stats_.link_faults;
    return false;
  }
  co.set_will(mqtt::will_options(OnlineTopic(), offline.data(), offline.size(), 1, true));
  try {
    if (!client_->client.connect(co)->wait_for(Ms(options_.connect_timeout_s + 0.5))) {
      std::lock_guard<std::mutex> lock(mu_);
      stats_.last_error = "connect: no answer within connect_timeout_s";
      ++stats_.link_faults;
      return false;
    }
    client_->client.publish(OnlineTopic(), online.data(), online.size(), 1, true)
        ->wait_for(Ms(options_.publish_timeout_s));
  } catch (const std::exception& e) {
    std::lock_guard<std::mutex> lock(mu_);
    stats_.last_error = std::string("connect: ") + e.what();
    ++stats_.link_faults;
    return false;
  }
  std::lock_guard<std::mutex> lock(mu_);
  ++stats_.connects;
  stats_.connected = true;
  // A broker that restarted has lost the retained values: every topic's last value goes again
  // (unless a newer one is already waiting).
  for (auto& [topic, payload] : sent_) {
    if (pending_.count(topic)) continue;
    order_.push_front(topic);
    pending_.emplace(topic, payload);
    ++stats_.republished;
  }
  sent_.clear();
  return true;
}

void MqttPublisher::Run() {
  double backoff_s = options_.reconnect_min_s;
  const long publish_timeout_ms = Ms(options_.publish_timeout_s);
  for (;;) {
    bool connected = false;
    {
      std::lock_guard<std::mutex> lock(mu_);
      connected = stats_.connected = stats_.connected && client_ && client_->client.is_connected();
      if (stop_ && (!connected || pending_.empty())) break;
    }
    if (!connected) {
      if (ConnectOnce()) {
        backoff_s = options_.reconnect_min_s;
      } else {
        Backoff(backoff_s);
      }
      continue;
    }
    // Up to max_in_flight values go out before the first acknowledgement is awaited.
    std::vector<std::pair<std::string, std::string>> batch;
    {
      std::unique_lock<std::mutex> lock(mu_);
      // Wake at least every 100 ms to notice a lost connection while idle.
      wake_.wait_for(lock, std::chrono::milliseconds(100), [&] { return stop_ || !pending_.empty(); });
      while (!pending_.empty() && batch.size() < static_cast<std::size_t>(options_.max_in_flight)) {
        std::string topic = std::move(order_.front());
        order_.pop_front();
        auto node = pending_.extract(topic);
        batch.emplace_back(std::move(topic), std::move(node.mapped()));
      }
      in_flight_ = batch.size();
      if (batch.empty()) continue;
    }
    std::vector<mqtt::delivery_token_ptr> tokens;
    std::vector<bool> acked(batch.size(), false);
    std::string error;
    try {
      for (const auto& [topic, payload] : batch)
        tokens.push_back(client_->client.publish(topic, payload.data(), payload.size(), options_.qos, options_.retain));
      for (std::size_t i = 0; i < tokens.size(); ++i) {
        acked[i] = tokens[i]->wait_for(publish_timeout_ms);
        if (!acked[i]) {
          error = "publish: not acknowledged within publish_timeout_s";
          break;
        }
      }
    } catch (const std::exception& e) {
      error = std::string("publish: ") + e.what();
    }
    {
      std::lock_guard<std::mutex> lock(mu_);
      in_flight_ = 0;
      if (!error.empty()) {
        ++stats_.link_faults;
        stats_.last_error = error;
        stats_.connected = false;
      }
      // Unacknowledged values go first after the reconnect, unless superseded meanwhile (newest first
      // into the front keeps their order).
      for (std::size_t i = batch.size(); i-- > 0;) {
        auto& [topic, payload] = batch[i];
        if (acked[i]) {
          ++stats_.published;
          sent_[topic] = std::move(payload);
        } else if (!pending_.count(topic)) {
          order_.push_front(topic);
          pending_.emplace(std::move(topic), std::move(payload));
        }
      }
    }
    progress_.notify_all();
    if (!error.empty()) {
      try {
        client_->client.disconnect(0)->wait_for(100L);
      } catch (const std::exception&) {
      }
    }
  }
  progress_.notify_all();
}

void MqttPublisher::Close() {
  {
    std::lock_guard<std::mutex> lock(mu_);
    if (stop_ && !thread_.joinable()) return;
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  try {
    if (client_ && client_->client.is_connected()) {
      const std::string offline = "offline";
      client_->client.publish(OnlineTopic(), offline.data(), offline.size(), 1, true)
          ->wait_for(Ms(options_.publish_timeout_s));
      client_->client.disconnect()->wait_for(Ms(options_.publish_timeout_s));
    }
  } catch (const std::exception&) {
    // the broker is gone: its last will says offline
  }
  std::lock_guard<std::mutex> lock(mu_);
  stats_.connected = false;
}

}  // namespace trueaxis::live
