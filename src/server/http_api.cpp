#include "trueaxis/server/http_api.hpp"

#include <chrono>
#include <cmath>
#include <thread>

#include <httplib.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/runtime/cycle_step.hpp"

namespace trueaxis::server {
namespace {

nlohmann::json Value(const Reading& r) { return r ? nlohmann::json(*r) : nlohmann::json(nullptr); }

nlohmann::json ToJson(const ModelInfo& m) {
  return {{"file", m.file}, {"sha256", m.sha256}, {"revision", m.revision}, {"slot", m.slot}};
}

}  // namespace

nlohmann::json ToJson(const MachineStatus& s) {
  nlohmann::json j = {{"name", s.name},
                      {"endpoint", s.endpoint},
                      {"connected", s.connected},
                      {"last_good_read_unix_s", s.last_good_read_unix_s > 0 ? nlohmann::json(s.last_good_read_unix_s) : nlohmann::json(nullptr)},
                      {"alarms", s.alarm_names},
                      {"alarm_bits", s.alarms},
                      {"unacknowledged", runtime::AlarmNames(s.unacknowledged)},
                      {"last_fault", s.last_fault},
                      {"cycles", s.cycles},
                      {"complete_cycles", s.complete_cycles},
                      {"faults", s.faults},
                      {"connects", s.connects},
                      {"overruns", s.overruns},
                      {"last_latency_ms", s.last_latency_ms},
                      {"coolant", s.coolant},
                      {"coolant_override", s.coolant_override ? nlohmann::json(*s.coolant_override) : nlohmann::json(nullptr)},
                      {"model", ToJson(s.model)}};
  for (const auto& a : s.axes)
    j["axes"].push_back({{"name", a.name},
                         {"position_mm", Value(a.position_mm)},
                         {"applied_um", Value(a.applied_um)},
                         {"target_um", std::isfinite(a.target_um) ? nlohmann::json(a.target_um) : nlohmann::json(nullptr)},
                         {"output_um", a.output_um},
                         {"enabled", a.enabled},
                         {"state", a.state}});
  for (const auto& c : s.channels) j["channels"].push_back({{"name", c.name}, {"temp_c", Value(c.temp_c)}, {"health", c.health}});
  return j;
}

nlohmann::json ToJson(const ModelChange& c) {
  return {{"machine", c.machine}, {"action", c.action}, {"user", c.user}, {"from", c.from}, {"time_unix_s", c.time_unix_s},
          {"old", ToJson(c.old_model)}, {"new", ToJson(c.new_model)}};
}

nlohmann::json ToJson(const ShopStats& s) {
  return {{"cycles", s.cycles},
          {"complete_cycles", s.complete_cycles},
          {"faults", s.faults},
          {"overruns", s.overruns},
          {"latency_p50_ms", s.latency_p50_ms},
          {"latency_p99_ms", s.latency_p99_ms},
          {"latency_max_ms", s.latency_max_ms},
          {"latency_samples", s.latency_samples},
          {"history_dropped", s.history_dropped}};
}

struct HttpApi::Impl {
  Shop& shop;
  httplib::Server http;
  std::thread thread;
  explicit Impl(Shop& s) : shop(s) {}

  static void Reply(httplib::Response& res, int status, const nlohmann::json& j) {
    res.status = status;
    res.set_content(j.dump(2) + "\n", "application/json");
  }

  // Runs `fn` with the request body as JSON; bad input → 400/404/422 with the message.
  template <typename Fn>
  static void Guard(const httplib::Request& req, httplib::Response& res, Fn fn) {
    nlohmann::json body = nlohmann::json::object();
    try {
      if (!req.body.empty()) body = nlohmann::json::parse(req.body);
      if (!body.is_object()) throw InputError("request", 0, "body", "must be a JSON object");
      fn(body);
    } catch (const InputError& e) {
      const bool unknown = e.field() == "machine" || e.field() == "axis";
      Reply(res, unknown ? 404 : e.source() == "request" || e.source() == "command line" ? 400 : 422, {{"error", e.what()}});
    } catch (const nlohmann::json::exception& e) {
      Reply(res, 400, {{"error", std::string("request body: ") + e.what()}});
    }
  }

  static std::string User(const nlohmann::json& body) {
    const std::string u = body.value("user", std::string());
    if (u.empty()) throw InputError("request", 0, "user", "missing (required): who makes the change");
    return u;
  }

  void Routes() {
    http.Get("/api/machines", [this](const httplib::Request&, httplib::Response& res) {
      nlohmann::json j = nlohmann::json::array();
      for (const auto& s : shop.Snapshot()) j.push_back(ToJson(s));
      Reply(res, 200, j);
    });
    http.Get("/api/stats", [this](const httplib::Request&, httplib::Response& res) { Reply(res, 200, ToJson(shop.Stats())); });
    http.Get(R"(/api/machines/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
      const auto s = shop.Machine(req.matches[1]);
      if (!s) return Reply(res, 404, {{"error", "no machine named '" + std::string(req.matches[1]) + "'"}});
      Reply(res, 200, ToJson(*s));
    });
    http.Get(R"(/api/machines/([^/]+)/models)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json&) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& c : shop.ModelChanges(req.matches[1])) j.push_back(ToJson(c));
        Reply(res, 200, j);
      });
    });
    http.Post(R"(/api/machines/([^/]+)/model)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        const std::string file = body.value("file", std::string());
        if (file.empty()) throw InputError("request", 0, "file", "missing (required): the model file on the server");
        Reply(res, 200, ToJson(shop.LoadModel(req.matches[1], file, User(body), req.remote_addr)));
      });
    });
    http.Post(R"(/api/machines/([^/]+)/rollback)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        Reply(res, 200, ToJson(shop.Rollback(req.matches[1], User(body), req.remote_addr)));
      });
    });
    http.Post(R"(/api/machines/([^/]+)/axes/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        if (!body.contains("enabled") || !body["enabled"].is_boolean())
          throw InputError("request", 0, "enabled", "missing (required): true or false");
        shop.SetAxisEnabled(req.matches[1], req.matches[2], body["enabled"].get<bool>(), User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
    http.Post(R"(/api/machines/([^/]+)/acknowledge)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        shop.AcknowledgeAlarms(req.matches[1], User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
    http.Post(R"(/api/machines/([^/]+)/coolant)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        std::optional<CoolantState> c;
        if (body.contains("override") && !body["override"].is_null()) {
          c = ParseCoolantState(body["override"].get<std::string>());
          if (!c) throw InputError("request", 0, "override", "must be off, flood, mist, air or null");
        }
        shop.SetCoolantOverride(req.matches[1], c, User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
  }
};

HttpApi::HttpApi(Shop& shop, std::string bind_address, int port)
    : impl_(std::make_unique<Impl>(shop)), bind_(std::move(bind_address)), port_(port) {
  impl_->Routes();
}

HttpApi::~HttpApi() { Stop(); }

bool HttpApi::Start(std::string* error) {
  if (port_ == 0) {
    port_ = impl_->http.bind_to_any_port(bind_.c_str());
  } else if (!impl_->http.bind_to_port(bind_.c_str(), port_)) {
    port_ = -1;
  }
  if (port_ <= 0) {
    if (error) *error = "cannot bind the HTTP API on " + bind_;
    return false;
  }
  impl_->thread = std::thread([this] { impl_->http.listen_after_bind(); });
  while (!impl_->http.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return true;
}

void HttpApi::Stop() {
  if (!impl_->thread.joinable()) return;
  impl_->http.stop();
  impl_->thread.join();
}

}  // namespace trueaxis::server
