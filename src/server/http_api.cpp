#include "trueaxis/server/http_api.hpp"

#include <arpa/inet.h>
#include <netdb.h>
#include <unistd.h>
#include <sys/socket.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <regex>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/server/gated_http_server.hpp"
#include "trueaxis/server/http_guard.hpp"

namespace trueaxis::server {
namespace {

nlohmann::json ModelJson(const ModelInfo& m) {
  nlohmann::json j = runtime::ModelViewJson(ModelViewOf(m));
  j["slot"] = m.slot;
  return j;
}

}  // namespace

runtime::MachineModelView ModelViewOf(const ModelInfo& m) {
  return {m.file.empty() ? "" : std::to_string(m.revision), m.sha256, m.file};
}

runtime::MachineView MachineViewOf(const MachineStatus& s) {
  runtime::MachineView v;
  v.id = s.name;
  v.name = s.name;
  v.connected = s.connected;
  if (s.last_good_read_unix_s > 0) v.updated_unix_s = s.last_good_read_unix_s;
  v.alarms = runtime::SplitAlarmNames(s.alarm_names);
  v.coolant = s.coolant;
  v.coolant_override = s.coolant_override.value_or("");
  v.model = ModelViewOf(s.model);
  const auto known = [](const Reading& r) { return r ? *r : runtime::kUnknown; };  // UNAVAILABLE is never a number
  for (const auto& a : s.axes)
    v.axes.push_back({a.name, a.enabled, a.state, known(a.position_mm), a.output_um, a.target_um, known(a.applied_um)});
  for (const auto& c : s.channels) v.channels.push_back({c.name, known(c.temp_c), c.health});
  return v;
}

nlohmann::json ToJson(const MachineStatus& s) {
  nlohmann::json j = runtime::MachineViewJson(MachineViewOf(s));
  j["endpoint"] = s.endpoint;
  j["alarm_bits"] = s.alarms;
  j["unacknowledged"] = runtime::SplitAlarmNames(runtime::AlarmNames(s.unacknowledged));
  j["last_fault"] = s.last_fault;
  j["cycles"] = s.cycles;
  j["complete_cycles"] = s.complete_cycles;
  j["faults"] = s.faults;
  j["connects"] = s.connects;
  j["overruns"] = s.overruns;
  j["last_latency_ms"] = s.last_latency_ms;
  j["model"]["slot"] = s.model.slot;
  return j;
}

nlohmann::json ToJson(const ModelChange& c) {
  return {{"machine", c.machine}, {"action", c.action}, {"user", c.user}, {"from", c.from}, {"time_unix_s", c.time_unix_s},
          {"old", ModelJson(c.old_model)}, {"new", ModelJson(c.new_model)}};
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
          {"latency_histogram", s.latency_histogram},  // [[upper edge ms, count], …]: the p99 of any window by difference
          {"history_dropped", s.history_dropped},
          {"poll_threads", s.poll_threads}};
}

namespace {

// Limits of the control API (docs/server.md): a request is a few hundred bytes; nothing a client
// sends is kept or echoed beyond these.
constexpr std::size_t kMaxBodyBytes = 64 * 1024;  // larger: 413
constexpr std::size_t kMaxUserChars = 200;        // "user": written to the audit log and the history
constexpr std::size_t kMaxFileChars = 4096;       // "file": a path (PATH_MAX)
// A connection reaches a worker only once its whole request has arrived (GatedHttpServer): idle or
// slow clients wait outside the pool and are dropped (408) when their request is not complete
// within the timeout. One request per connection, so an idle keep-alive never holds a worker either.
constexpr std::size_t kWorkers = 32;
constexpr time_t kIoTimeoutS = 2;

std::size_t Utf8Chars(const std::string& s) {
  return static_cast<std::size_t>(std::count_if(s.begin(), s.end(), [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}

// A field of the request body that is out of range (rather than missing or mistyped): 422.
struct FieldValueError : InputError {
  using InputError::InputError;
};

// "user" / "file": a JSON string, present, not empty, at most `max` characters.
std::string StringField(const nlohmann::json& body, const char* name, std::size_t max, const char* what) {
  if (!body.contains(name) || body[name].is_null()) throw InputError("request", 0, name, std::string("missing (required): ") + what);
  if (!body[name].is_string()) throw InputError("request", 0, name, "must be a string");
  std::string v = body[name].get<std::string>();
  if (v.empty()) throw InputError("request", 0, name, std::string("missing (required): ") + what);
  if (Utf8Chars(v) > max) throw FieldValueError("request", 0, name, fmt::format("longer than {} characters", max));
  return v;
}

}  // namespace

bool CanListen(const std::string& bind_address, int port, std::string* error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  bool ok = getaddrinfo(bind_address.c_str(), service.c_str(), &hints, &found) == 0 && found;
  if (ok) {
    const int fd = ::socket(found->ai_family, found->ai_socktype, found->ai_protocol);
    int yes = 1;
    ok = fd >= 0 && ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes) == 0 &&
         ::bind(fd, found->ai_addr, found->ai_addrlen) == 0 && ::listen(fd, 1) == 0;
    if (fd >= 0) ::close(fd);
  }
  if (found) freeaddrinfo(found);
  if (!ok && error)
    *error = fmt::format("cannot listen on {}:{} (in use by another program, or not an address of this computer)", bind_address, port);
  return ok;
}

bool IsLoopbackAddress(const std::string& address) {
  if (address == "localhost" || address == "::1") return true;
  in_addr a{};
  if (inet_pton(AF_INET, address.c_str(), &a) != 1) return false;
  return (ntohl(a.s_addr) >> 24) == 127;
}

struct HttpApi::Impl {
  Shop& shop;
  GatedHttpServer http{kWorkers, static_cast<double>(kIoTimeoutS), kMaxBodyBytes};
  std::thread thread;
  int port = 0;  // the bound port (for the same-origin check)
  int listen_socket = -1;
  std::string bind;
  struct Route {
    std::regex path;
    std::string method;
  };
  std::vector<Route> routes;  // to tell a wrong method (405) from an unknown path (404)
  explicit Impl(Shop& s, std::string b) : shop(s), bind(std::move(b)) {}

  static void Reply(httplib::Response& res, int status, const nlohmann::json& j) { ReplyJsonText(res, status, j.dump(2) + "\n"); }
  // The body moved in, not copied (set_content copies: a thousand machines' JSON is megabytes).
  static void ReplyJsonText(httplib::Response& res, int status, std::string&& text) {
    res.status = status;
    res.body = std::move(text);
    res.set_header("Content-Type", "application/json");
  }
  static void Error(httplib::Response& res, int status, const std::string& message) { Reply(res, status, {{"error", message}}); }

  // The control API has no authentication: a page in a browser on this computer must not be able
  // to drive it. Browsers send Origin on every cross-site POST; the CLI sends none.
  bool SameOrigin(const std::string& origin) const {
    if (origin.empty()) return true;
    std::vector<std::string> own = {fmt::format("http://127.0.0.1:{}", port), fmt::format("http://localhost:{}", port),
                                    fmt::format("http://[::1]:{}", port)};
    if (bind != "0.0.0.0" && bind != "::" && !bind.empty()) own.push_back(fmt::format("http://{}:{}", bind, port));
    return std::find(own.begin(), own.end(), origin) != own.end();
  }

  // Runs `fn` with the request body as JSON; bad input → 400/404/422 with the message.
  template <typename Fn>
  static void Guard(const httplib::Request& req, httplib::Response& res, Fn fn) {
    try {
      nlohmann::json body = nlohmann::json::object();
      if (!req.body.empty()) {
        body = nlohmann::json::parse(req.body, nullptr, /*allow_exceptions=*/false);
        if (body.is_discarded()) throw InputError("request", 0, "body", "not valid JSON");
      } else if (req.method == "POST") {
        throw InputError("request", 0, "body", "missing (required): a JSON object such as {\"user\": \"alice\"}");
      }
      if (!body.is_object()) throw InputError("request", 0, "body", "must be a JSON object");
      fn(body);
    } catch (const FieldValueError& e) {
      Error(res, 422, e.what());
    } catch (const InputError& e) {
      const bool unknown = e.field() == "machine" || e.field() == "axis";
      const bool server = e.field() == "audit_log";  // the server could not record the change: not the client's fault
      Error(res, server ? 500 : unknown ? 404 : e.source() == "request" || e.source() == "command line" ? 400 : 422, e.what());
    } catch (const nlohmann::json::exception&) {
      Error(res, 400, "request body: a field has the wrong type");
    }
  }

  static std::string User(const nlohmann::json& body) {
    return StringField(body, "user", kMaxUserChars, "who makes the change");
  }

  template <typename H>
  void Get(const std::string& pattern, H handler) {
    routes.push_back({std::regex(pattern), "GET"});
    http.Get(pattern, handler);
  }
  template <typename H>
  void Post(const std::string& pattern, H handler) {
    routes.push_back({std::regex(pattern), "POST"});
    http.Post(pattern, handler);
  }

  void Configure() {
    http.set_keep_alive_max_count(1);
    http.set_keep_alive_timeout(kIoTimeoutS);  // a connection that sends nothing is closed after this
    http.set_read_timeout(kIoTimeoutS, 0);
    http.set_write_timeout(kIoTimeoutS, 0);
    http.set_payload_max_length(kMaxBodyBytes);
    // cpp-httplib's default socket options add SO_REUSEPORT, which lets a second server bind the
    // same port and take half of the requests. SO_REUSEADDR only (as the web front end): a port in
    // use is refused.
    // cpp-httplib listens with a backlog of 5: more clients connecting at once wait for SYN
    // retries (seconds). Start() listens again with the system's maximum, as the web front end.
    http.set_socket_options([this](socket_t sock) {
      int yes = 1;
      ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const char*>(&yes), sizeof yes);
      listen_socket = static_cast<int>(sock);
    });
    // Before the body is read: another site's page (403) and a body that is not JSON (415; a
    // browser sends text/plain cross-site without asking first).
    http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
      // DNS rebinding (http_guard.hpp): only this computer's names and IP addresses are served.
      if (const std::string host = req.get_header_value("Host"); !IsOwnHost(host, bind)) {
        Error(res, 403, "request: field 'Host': '" + host.substr(0, 200) + "' is not this server's name (DNS rebinding?)");
        return httplib::Server::HandlerResponse::Handled;
      }
      const std::string origin = req.get_header_value("Origin");
      if (!SameOrigin(origin)) {
        Error(res, 403, "request: field 'Origin': cross-origin request refused (Origin " + origin.substr(0, 200) + ")");
        return httplib::Server::HandlerResponse::Handled;
      }
      // A chunked body, or one without its length, would be read whole before the size limit
      // applies; a length over the limit is refused before the body is read.
      if (const auto refusal = CheckBodyFraming(req, kMaxBodyBytes)) {
        Error(res, refusal->status, refusal->message);
        return httplib::Server::HandlerResponse::Handled;
      }
      if (req.method == "POST" && !IsJsonMediaType(req.get_header_value("Content-Type"))) {
        Error(res, 415, "request: field 'Content-Type': must be application/json");
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    // Every error is JSON; a known path with the wrong method is 405.
    http.set_error_handler(httplib::Server::HandlerWithResponse([this](const httplib::Request& req, httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      if (res.status == 404) {
        std::string allow;
        for (const auto& r : routes)
          if (std::regex_match(req.path, r.path) && allow.find(r.method) == std::string::npos) allow += (allow.empty() ? "" : ", ") + r.method;
        if (!allow.empty()) {
          res.set_header("Allow", allow);
          Error(res, 405, fmt::format("method {} not allowed on {} (allowed: {})", req.method.substr(0, 16), req.path.substr(0, 200), allow));
          return httplib::Server::HandlerResponse::Handled;
        }
        Error(res, 404, "no such endpoint (see docs/server.md)");
        return httplib::Server::HandlerResponse::Handled;
      }
      Error(res, res.status, res.status == 413 ? fmt::format("request body: larger than {} bytes", kMaxBodyBytes)
                                               : "bad request");
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
      Error(res, 500, "internal error");
    });
  }

  void Routes() {
    Get("/api/machines", [this](const httplib::Request&, httplib::Response& res) {
      // One machine at a time — its status copied, its JSON made and written out, then freed — so
      // a shop of thousands never holds every machine's status and JSON tree at once.
      std::string text = "[";
      const std::size_t n = shop.MachineCount();
      for (std::size_t i = 0; i < n; ++i) {
        text += i == 0 ? "\n" : ",\n";
        text += ToJson(shop.MachineAt(i)).dump(2);
      }
      text += n == 0 ? "]\n" : "\n]\n";
      ReplyJsonText(res, 200, std::move(text));
    });
    Get("/api/stats", [this](const httplib::Request&, httplib::Response& res) { Reply(res, 200, ToJson(shop.Stats())); });
    Get(R"(/api/machines/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
      const auto s = shop.Machine(req.matches[1]);
      if (!s) return Error(res, 404, "no machine named '" + std::string(req.matches[1]) + "'");
      Reply(res, 200, ToJson(*s));
    });
    Get(R"(/api/machines/([^/]+)/models)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json&) {
        nlohmann::json j = nlohmann::json::array();
        for (const auto& c : shop.ModelChanges(req.matches[1])) j.push_back(ToJson(c));
        Reply(res, 200, j);
      });
    });
    Post(R"(/api/machines/([^/]+)/model)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        const std::string file = StringField(body, "file", kMaxFileChars, "the model file on the server");
        Reply(res, 200, ToJson(shop.LoadModel(req.matches[1], file, User(body), req.remote_addr)));
      });
    });
    Post(R"(/api/machines/([^/]+)/rollback)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        Reply(res, 200, ToJson(shop.Rollback(req.matches[1], User(body), req.remote_addr)));
      });
    });
    Post(R"(/api/machines/([^/]+)/axes/([^/]+))", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        if (!body.contains("enabled") || body["enabled"].is_null())
          throw InputError("request", 0, "enabled", "missing (required): true or false");
        if (!body["enabled"].is_boolean()) throw InputError("request", 0, "enabled", "must be true or false");
        shop.SetAxisEnabled(req.matches[1], req.matches[2], body["enabled"].get<bool>(), User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
    Post(R"(/api/machines/([^/]+)/acknowledge)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        shop.AcknowledgeAlarms(req.matches[1], User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
    Post(R"(/api/machines/([^/]+)/coolant)", [this](const httplib::Request& req, httplib::Response& res) {
      Guard(req, res, [&](const nlohmann::json& body) {
        std::optional<CoolantState> c;
        // Required: a body without it cleared the override as if null had been sent.
        if (!body.contains("override"))
          throw InputError("request", 0, "override", "missing (required): off, flood, mist, air, or null to clear the override");
        if (!body["override"].is_null()) {
          if (body["override"].is_string()) c = ParseCoolantState(body["override"].get<std::string>());
          if (!c) throw InputError("request", 0, "override", "must be off, flood, mist, air or null");
        }
        shop.SetCoolantOverride(req.matches[1], c, User(body));
        Reply(res, 200, ToJson(*shop.Machine(req.matches[1])));
      });
    });
  }
};

HttpApi::HttpApi(Shop& shop, std::string bind_address, int port)
    : impl_(std::make_unique<Impl>(shop, bind_address)), bind_(std::move(bind_address)), port_(port) {
  impl_->Configure();
  impl_->Routes();
}

HttpApi::~HttpApi() { Stop(); }

bool HttpApi::Start(std::string* error) {
  const int wanted = port_;
  if (port_ == 0) {
    port_ = impl_->http.bind_to_any_port(bind_.c_str());
  } else if (!impl_->http.bind_to_port(bind_.c_str(), port_)) {
    port_ = -1;
  }
  if (port_ <= 0) {
    if (error)
      *error = wanted == 0 ? fmt::format("cannot listen on {} (not an address of this computer?)", bind_)
                           : fmt::format("cannot listen on {}:{} (in use by another program, or not an address of this computer)",
                                         bind_, wanted);
    return false;
  }
  impl_->port = port_;
  if (impl_->listen_socket >= 0) ::listen(impl_->listen_socket, SOMAXCONN);
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
