#include "trueaxis/server/mtconnect_agent.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <iterator>
#include <thread>
#include <unordered_map>

#include <fmt/format.h>
#include <httplib.h>
#include <pugixml.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/periodic_thread.hpp"
#include "trueaxis/runtime/cycle_step.hpp"
#include "trueaxis/server/gated_http_server.hpp"
#include "trueaxis/server/http_guard.hpp"
#include "trueaxis/server/mtconnect_buffer.hpp"
#include "trueaxis/server/mtconnect_devices.hpp"
#include "trueaxis/server/mtconnect_documents.hpp"

namespace trueaxis::server {

using namespace mtconnect;

namespace {

constexpr std::size_t kWorkers = 8;
constexpr double kRequestTimeoutS = 2;
constexpr std::size_t kMaxBodyBytes = 0;    // a request is a GET without a body
constexpr std::size_t kDefaultCount = 100;  // /sample without count (the standard's default)

double UnixNowS() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

// Alarms that stop or void the compensation: Fault; the others (a sensor held or on its fallback, the
// correction clamped, the model extrapolated): Warning.
constexpr std::uint32_t kFaultAlarms = runtime::kAlarmTemperatureSource | runtime::kAlarmLinkRead | runtime::kAlarmLinkWrite |
                                       runtime::kAlarmNoModelForAxis | runtime::kAlarmNoModel | runtime::kAlarmStaleInput |
                                       runtime::kAlarmVisionStop;

template <typename... Args>
void Format(std::string& out, fmt::format_string<Args...> f, Args&&... args) {
  out.clear();
  fmt::format_to(std::back_inserter(out), f, std::forward<Args>(args)...);
}

void Set(std::string& out, const char* text) { out.assign(text); }

// The item's value as the documents show it, into `o` (its strings reused).
void ValueOf(const DataItem& item, const MachineStatus& m, Observation& o) {
  o.native_code.clear();
  o.text.clear();
  const bool axis = item.source == Source::kPosition || item.source == Source::kApplied || item.source == Source::kCommanded ||
                    item.source == Source::kAxisState;
  const bool channel = item.source == Source::kTemperature || item.source == Source::kChannelHealth;
  if ((axis && item.index >= m.axes.size()) || (channel && item.index >= m.channels.size())) {
    Set(o.value, item.category == Category::kCondition ? "Unavailable" : "UNAVAILABLE");
    return;
  }
  switch (item.source) {
    case Source::kAvailability:
      Set(o.value, m.connected ? "AVAILABLE" : "UNAVAILABLE");
      return;
    case Source::kSystem: {
      if (m.alarms == 0) return Set(o.value, "Normal");
      Set(o.value, (m.alarms & kFaultAlarms) ? "Fault" : "Warning");
      o.native_code = m.alarm_names;
      o.text = m.alarm_names;
      if (!m.connected && !m.last_fault.empty()) o.text += ": " + m.last_fault;
      return;
    }
    case Source::kPosition: {
      const auto& p = m.axes[item.index].position_mm;
      if (m.connected && p && std::isfinite(*p)) return Format(o.value, "{:.4f}", *p);
      return Set(o.value, "UNAVAILABLE");
    }
    case Source::kApplied: {
      const auto& a = m.axes[item.index].applied_um;
      if (m.connected && a && std::isfinite(*a)) return Format(o.value, "{:.5f}", *a / 1000.0);
      return Set(o.value, "UNAVAILABLE");
    }
    case Source::kCommanded: {
      const double c = m.axes[item.index].output_um;
      if (m.connected && std::isfinite(c)) return Format(o.value, "{:.5f}", c / 1000.0);
      return Set(o.value, "UNAVAILABLE");
    }
    case Source::kAxisState:
      o.value = m.axes[item.index].state;
      return;
    case Source::kTemperature: {
      const auto& t = m.channels[item.index].temp_c;
      if (m.connected && t && std::isfinite(*t)) return Format(o.value, "{:.3f}", *t);
      return Set(o.value, "UNAVAILABLE");
    }
    case Source::kChannelHealth: {
      const std::string& h = m.channels[item.index].health;
      if (!m.connected) return Set(o.value, "Unavailable");
      if (h == "ok") return Set(o.value, "Normal");
      Set(o.value, h == "held" ? "Warning" : "Fault");
      o.native_code = h;
      o.text = h == "held" ? "sensor faulty: its last good value is used" : "sensor lost";
      return;
    }
  }
}

bool SameValue(const Observation& a, const Observation& b) {
  return a.value == b.value && a.native_code == b.native_code && a.text == b.text;
}

std::string HostName() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || !name[0]) return "trueaxis";
  return name;
}

// The query of a request target, each parameter split at its first '=': an XPath such as
// path=//DataItem[@type="POSITION"] is usually sent with its '=' as is (cpp-httplib's own parser
// splits such a parameter at the wrong '=').
std::multimap<std::string, std::string> Query(const std::string& target) {
  std::multimap<std::string, std::string> params;
  const auto q = target.find('?');
  if (q == std::string::npos) return params;
  for (std::size_t i = q + 1; i <= target.size();) {
    const std::size_t end = std::min(target.find('&', i), target.size());
    const std::string part = target.substr(i, end - i);
    if (!part.empty()) {
      const auto eq = part.find('=');
      params.emplace(httplib::detail::decode_url(part.substr(0, eq), true),
                     eq == std::string::npos ? "" : httplib::detail::decode_url(part.substr(eq + 1), true));
    }
    i = end + 1;
  }
  return params;
}

struct QueryError {
  std::string code, message;
};

const std::string* Param(const std::multimap<std::string, std::string>& params, const char* name) {
  const auto it = params.find(name);
  return it == params.end() ? nullptr : &it->second;
}

// A sequence number or count: digits only, at most 19 of them.
std::optional<std::uint64_t> Unsigned(const std::multimap<std::string, std::string>& params, const char* name) {
  const std::string* v = Param(params, name);
  if (!v) return std::nullopt;
  if (v->empty() || v->size() > 19 || v->find_first_not_of("0123456789") != std::string::npos)
    throw QueryError{"QUERY_ERROR", fmt::format("'{}' must be a positive integer, not '{}'", name, XmlSafe(*v, 40))};
  return std::stoull(*v);
}

}  // namespace

struct MtconnectAgent::Impl {
  const Shop& shop;
  MtconnectOptions options;
  DeviceModel model;
  ObservationBuffer buffer;
  std::uint64_t instance_id;
  pugi::xml_document probe;  // the Devices document, to evaluate `path`
  std::unordered_map<std::string, std::uint32_t> item_of_id;
  // The publisher's own state (its thread, or a test calling PublishOnce).
  std::vector<Observation> published, batch;
  Observation scratch;
  // HTTP
  GatedHttpServer http{kWorkers, kRequestTimeoutS, kMaxBodyBytes};
  std::thread thread;
  int listen_socket = -1;
  core::PeriodicThread worker;  // last: stopped first

  Impl(const Shop& s, MtconnectOptions o)
      : shop(s), options(std::move(o)), model(BuildDeviceModel(s.Snapshot())), buffer(options.buffer_size, model.items.size()),
        instance_id(static_cast<std::uint64_t>(std::max(1.0, std::floor(UnixNowS())))) {
    if (options.sender.empty()) options.sender = HostName();
    options.sender = XmlSafe(options.sender);
    BuildDevices(model, Header(), -1, probe);
    for (std::uint32_t i = 0; i < model.items.size(); ++i) item_of_id[model.items[i].id] = i;
    // Every data item starts UNAVAILABLE (the standard's initial value) until the publisher has seen it.
    const double now = UnixNowS();
    published.resize(model.items.size());
    batch.resize(model.items.size());
    for (std::uint32_t i = 0; i < model.items.size(); ++i) {
      published[i].item = batch[i].item = i;
      published[i].value = model.items[i].category == Category::kCondition ? "Unavailable" : "UNAVAILABLE";
      batch[i] = published[i];
      batch[i].time_unix_s = now;
    }
    buffer.Append(batch);
  }

  HeaderInfo Header() const { return {options.sender, instance_id, options.buffer_size, UnixNowS()}; }

  void PublishOnce() {
    const auto machines = shop.Snapshot();
    if (machines.size() != model.devices.size()) return;  // never: a shop's machines are fixed
    const double now = UnixNowS();
    std::size_t n = 0;
    for (std::uint32_t i = 0; i < model.items.size(); ++i) {
      const DataItem& item = model.items[i];
      ValueOf(item, machines[item.device], scratch);
      if (SameValue(scratch, published[i])) continue;
      published[i].value = scratch.value;
      published[i].native_code = scratch.native_code;
      published[i].text = scratch.text;
      Observation& o = batch[n++];
      o.item = i;
      o.time_unix_s = now;
      o.value = scratch.value;
      o.native_code = scratch.native_code;
      o.text = scratch.text;
    }
    if (n > 0) buffer.Append(std::span<Observation>(batch.data(), n));
  }

  // The data items a request asks for: one device's (device >= 0) and/or those `path` selects.
  std::optional<std::vector<bool>> Wanted(int device, const std::string* path) const {
    if (device < 0 && !path) return std::nullopt;
    std::vector<bool> wanted(model.items.size(), !path);
    if (path) {
      pugi::xpath_node_set found;
      try {
        found = probe.select_nodes(path->c_str());
      } catch (const pugi::xpath_exception& e) {
        throw QueryError{"INVALID_XPATH", fmt::format("the path '{}' is not a valid XPath: {}", XmlSafe(*path), e.what())};
      }
      auto mark = [&](pugi::xml_node n) {
        if (std::string_view(n.name()) != "DataItem") return;
        if (const auto it = item_of_id.find(n.attribute("id").value()); it != item_of_id.end()) wanted[it->second] = true;
      };
      for (const auto& x : found) {
        const pugi::xml_node n = x.node() ? x.node() : x.parent();
        mark(n);
        for (const pugi::xpath_node& d : n.select_nodes(".//DataItem")) mark(d.node());
      }
    }
    if (device >= 0)
      for (std::size_t i = 0; i < wanted.size(); ++i) wanted[i] = wanted[i] && static_cast<int>(model.items[i].device) == device;
    return wanted;
  }

  MtconnectResponse Error(int status, const std::string& code, const std::string& message) const {
    return {status, ErrorDocument(Header(), code, message)};
  }

  MtconnectResponse Current(int device, const std::multimap<std::string, std::string>& params) const {
    if (Param(params, "interval")) {
      if (Param(params, "at")) throw QueryError{"INVALID_REQUEST", "'at' and 'interval' cannot be used together"};
      throw QueryError{"UNSUPPORTED", "'interval' (streaming) is not served by this agent: poll /sample with from=nextSequence"};
    }
    const auto at = Unsigned(params, "at");
    const auto wanted = Wanted(device, Param(params, "path"));
    std::vector<Observation> found;
    BufferRange range;
    if (!buffer.Current(at, wanted ? &*wanted : nullptr, found, range))
      throw QueryError{"OUT_OF_RANGE", fmt::format("'at' must be between firstSequence {} and lastSequence {}", range.first, range.last)};
    return {200, StreamsDocument(model, Header(), range, at ? *at + 1 : range.next, std::move(found), device)};
  }

  MtconnectResponse Sample(int device, const std::multimap<std::string, std::string>& params) const {
    if (Param(params, "interval"))
      throw QueryError{"UNSUPPORTED", "'interval' (streaming) is not served by this agent: poll /sample with from=nextSequence"};
    const auto count = Unsigned(params, "count").value_or(kDefaultCount);
    if (count < 1 || count > options.buffer_size)
      throw QueryError{"OUT_OF_RANGE", fmt::format("'count' must be between 1 and bufferSize {}", options.buffer_size)};
    const auto from = Unsigned(params, "from");
    const auto wanted = Wanted(device, Param(params, "path"));
    std::vector<Observation> found;
    BufferRange range;
    std::uint64_t next = 0;
    if (!buffer.Sample(from, count, wanted ? &*wanted : nullptr, found, &next, range))
      throw QueryError{"OUT_OF_RANGE", fmt::format("'from' must be between firstSequence {} and nextSequence {} (it is {})", range.first,
                                                   range.next, from.value_or(0))};
    return {200, StreamsDocument(model, Header(), range, next, std::move(found), device)};
  }

  MtconnectResponse Respond(const std::string& path, const std::multimap<std::string, std::string>& params) const {
    std::vector<std::string> parts;
    for (std::size_t i = 0; i < path.size();) {
      const std::size_t j = std::min(path.find('/', i), path.size());
      if (j > i) parts.push_back(path.substr(i, j - i));
      i = j + 1;
    }
    try {
      int device = -1;
      std::string request = "probe";
      const auto is_request = [](const std::string& p) { return p == "probe" || p == "current" || p == "sample"; };
      if (!parts.empty() && (parts[0] == "assets" || parts[0] == "asset"))
        return Error(400, "UNSUPPORTED", "this agent publishes no assets: probe, current or sample");
      if (parts.size() == 1 && is_request(parts[0])) {
        request = parts[0];
      } else if (!parts.empty() && parts.size() <= 2) {
        device = model.Find(parts[0]);
        if (device < 0) return Error(404, "NO_DEVICE", fmt::format("no device named '{}' (GET /probe lists them)", XmlSafe(parts[0])));
        if (parts.size() == 2) request = parts[1];
      } else if (parts.size() > 2) {
        request.clear();
      }
      if (request == "probe") return {200, DevicesDocument(model, Header(), device)};
      if (request == "current") return Current(device, params);
      if (request == "sample") return Sample(device, params);
      return Error(404, "INVALID_URI", fmt::format("'{}' is not an MTConnect request: probe, current or sample", XmlSafe(path)));
    } catch (const QueryError& e) {
      return Error(400, e.code, e.message);
    }
  }

  void Configure() {
    http.set_keep_alive_max_count(1);
    http.set_read_timeout(static_cast<time_t>(kRequestTimeoutS), 0);
    http.set_write_timeout(static_cast<time_t>(kRequestTimeoutS), 0);
    http.set_payload_max_length(kMaxBodyBytes);
    // SO_REUSEADDR only (as the control API): a port in use is refused rather than shared.
    http.set_socket_options([this](socket_t sock) {
      int yes = 1;
      ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const char*>(&yes), sizeof yes);
      listen_socket = static_cast<int>(sock);
    });
    auto reply = [](httplib::Response& res, const MtconnectResponse& r) {
      res.status = r.status;
      res.set_content(r.body, "text/xml");
    };
    http.set_pre_routing_handler([this, reply](const httplib::Request& req, httplib::Response& res) {
      if (const std::string host = req.get_header_value("Host"); !IsOwnHost(host, options.bind, options.host_names)) {
        reply(res, Error(403, "UNAUTHORIZED", "the Host '" + XmlSafe(host) + "' is not this server's name (DNS rebinding?)"));
        return httplib::Server::HandlerResponse::Handled;
      }
      if (req.method != "GET" && req.method != "HEAD") {
        res.set_header("Allow", "GET, HEAD");
        reply(res, Error(405, "UNSUPPORTED", "only GET requests are served"));
        return httplib::Server::HandlerResponse::Handled;
      }
      if (const auto refusal = CheckBodyFraming(req, kMaxBodyBytes)) {
        reply(res, Error(refusal->status, "INVALID_REQUEST", refusal->message));
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    http.Get(".*", [this, reply](const httplib::Request& req, httplib::Response& res) { reply(res, Respond(req.path, Query(req.target))); });
    http.set_error_handler(httplib::Server::HandlerWithResponse([this, reply](const httplib::Request&, httplib::Response& res) {
      if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
      reply(res, Error(res.status, "INVALID_REQUEST", "bad request"));
      return httplib::Server::HandlerResponse::Handled;
    }));
    http.set_exception_handler([this, reply](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
      reply(res, Error(500, "INTERNAL_ERROR", "internal error"));
    });
  }
};

void CheckMtconnectOptions(const MtconnectOptions& options) {
  if (options.port < 0 || options.port > 65535)
    throw InputError("command line", 0, "--mtconnect", fmt::format("port {} is out of range: 0 to 65535", options.port));
  if (!(options.period_s > 0) || !std::isfinite(options.period_s) || options.period_s > 3600)
    throw InputError("command line", 0, "--mtconnect-period-s", fmt::format("{} is out of range: above 0, at most 3600 s", options.period_s));
  if (options.buffer_size < 16 || options.buffer_size > (1u << 24))
    throw InputError("command line", 0, "--mtconnect-buffer",
                     fmt::format("{} is out of range: 16 to {} observations", options.buffer_size, 1u << 24));
}

MtconnectAgent::MtconnectAgent(const Shop& shop, MtconnectOptions options) : port_(options.port) {
  CheckMtconnectOptions(options);
  impl_ = std::make_unique<Impl>(shop, std::move(options));
  impl_->Configure();
}

MtconnectAgent::~MtconnectAgent() { Stop(); }

void MtconnectAgent::PublishOnce() { impl_->PublishOnce(); }

MtconnectResponse MtconnectAgent::Respond(const std::string& path, const std::multimap<std::string, std::string>& params) const {
  return impl_->Respond(path, params);
}

bool MtconnectAgent::Start(std::string* error) {
  const std::string& bind = impl_->options.bind;
  const int wanted = port_;
  port_ = wanted == 0 ? impl_->http.bind_to_any_port(bind.c_str()) : impl_->http.bind_to_port(bind.c_str(), wanted) ? wanted : -1;
  if (port_ <= 0) {
    if (error)
      *error = fmt::format("cannot listen on {}:{} (in use by another program, or not an address of this computer)", bind, wanted);
    return false;
  }
  if (impl_->listen_socket >= 0) ::listen(impl_->listen_socket, SOMAXCONN);
  impl_->thread = std::thread([this] { impl_->http.listen_after_bind(); });
  while (!impl_->http.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  impl_->worker.Start(impl_->options.period_s, [this](double) { impl_->PublishOnce(); });
  return true;
}

void MtconnectAgent::Stop() {
  impl_->worker.Stop();
  if (!impl_->thread.joinable()) return;
  impl_->http.stop();
  impl_->thread.join();
}

}  // namespace trueaxis::server
