#include "trueaxis/web/web_server.hpp"

#include <httplib.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/install_paths.hpp"
#include "trueaxis/server/gated_http_server.hpp"
#include "trueaxis/server/http_guard.hpp"
#include "trueaxis/web/backend_json.hpp"
#include "trueaxis/web/machine_query.hpp"
#include "trueaxis/web/password_hash.hpp"

namespace trueaxis::web {

namespace fs = std::filesystem;
using nlohmann::json;

std::string DefaultStaticDir() {
  const DataFolder pages = FindDataFolder("web", "src/web/static");
  if (!pages.found())
    throw InputError("--web-root", "no web pages folder found (looked in " + pages.LookedIn() +
                                       "): install trueaxis (docs/install.md) or give --web-root FOLDER");
  return pages.path.string();
}

namespace {

constexpr const char* kCookieName = "ta_session";
constexpr const char* kIdPattern = "([A-Za-z0-9_.\\-]{1,64})";

double SteadyNowS() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
double UnixNowS() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

// A request the client got wrong (400) or is not allowed to make (status given).
struct HttpError : std::runtime_error {
  HttpError(int s, const std::string& m) : std::runtime_error(m), status(s) {}
  int status;
};

void SendJson(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}
void SendError(httplib::Response& res, int status, const std::string& message) {
  SendJson(res, status, json{{"error", message}});
}

std::string ContentTypeOf(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".ico") return "image/x-icon";
  return "application/octet-stream";
}

std::string ReadWholeFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) throw InputError(p.string(), "cannot read");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string CookieValue(const httplib::Request& req, const std::string& name) {
  const std::string header = req.get_header_value("Cookie");
  std::size_t pos = 0;
  while (pos < header.size()) {
    std::size_t end = header.find(';', pos);
    if (end == std::string::npos) end = header.size();
    std::string part = header.substr(pos, end - pos);
    const auto first = part.find_first_not_of(' ');
    if (first != std::string::npos) part = part.substr(first);
    if (part.rfind(name + "=", 0) == 0) return part.substr(name.size() + 1);
    pos = end + 1;
  }
  return "";
}

double ParamNumber(const httplib::Request& req, const char* name, double fallback) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used != text.size() || !std::isfinite(v)) throw std::invalid_argument("");
    return v;
  } catch (const std::exception&) {
    throw HttpError(400, fmt::format("query parameter '{}': '{}' is not a number", name, text));
  }
}
std::size_t ParamCount(const httplib::Request& req, const char* name, std::size_t fallback, std::size_t max) {
  const double v = ParamNumber(req, name, static_cast<double>(fallback));
  if (v < 0 || v != std::floor(v) || v > static_cast<double>(max))
    throw HttpError(400, fmt::format("query parameter '{}': must be a whole number from 0 to {}", name, max));
  return static_cast<std::size_t>(v);
}
const json& Field(const json& body, const char* name) {
  if (!body.contains(name)) throw HttpError(400, fmt::format("body: field '{}' is missing", name));
  return body.at(name);
}
bool BoolField(const json& body, const char* name) {
  const json& v = Field(body, name);
  if (!v.is_boolean()) throw HttpError(400, fmt::format("body: field '{}' must be true or false", name));
  return v.get<bool>();
}
std::string StringField(const json& body, const char* name, std::size_t max_length = 256) {
  const json& v = Field(body, name);
  if (!v.is_string()) throw HttpError(400, fmt::format("body: field '{}' must be a string", name));
  std::string s = v.get<std::string>();
  if (s.size() > max_length) throw HttpError(400, fmt::format("body: field '{}' is longer than {}", name, max_length));
  return s;
}
json ParseBody(const httplib::Request& req) {
  if (req.body.empty()) return json::object();
  if (!server::IsJsonMediaType(req.get_header_value("Content-Type"))) throw HttpError(415, "the body must be application/json");
  json body = json::parse(req.body, nullptr, /*allow_exceptions=*/false);
  if (body.is_discarded()) throw HttpError(400, "the body is not valid JSON");
  if (!body.is_object()) throw HttpError(400, "the body must be a JSON object");
  return body;
}
std::string Remote(const httplib::Request& req) { return fmt::format("{}:{}", req.remote_addr, req.remote_port); }

// A POST from another site's page is refused: its Origin (sent by every browser on a POST) must
// be this server exactly — scheme, host and port.
void CheckSameOrigin(const httplib::Request& req, bool tls) {
  const std::string origin = req.get_header_value("Origin");
  if (origin.empty()) return;
  if (!server::IsSameOrigin(origin, tls ? "https" : "http", req.get_header_value("Host")))
    throw HttpError(403, "cross-origin request refused (Origin " + origin.substr(0, 200) + ")");
}

}  // namespace

struct WebServer::Call {
  const httplib::Request& req;
  httplib::Response& res;
  Session session;
  json body;
  std::string target, detail;  // for the audit log
  Actor who() const { return {session.user, Remote(req)}; }
  bool sent = false;           // the handler wrote the response itself (a file)
};

WebServer::WebServer(MonitorBackend& backend, AccessDb& access, WebServerOptions options)
    : backend_(backend), access_(access), options_(std::move(options)), sessions_(options_.sessions),
      limiter_(options_.login), refusals_(access) {
  if (options_.static_dir.empty()) options_.static_dir = DefaultStaticDir();
  if (options_.tls_cert_file.empty() != options_.tls_key_file.empty())
    throw InputError("--web-cert/--web-key", "give both the certificate and its key, or neither");
  LoadStaticFiles();
  if (tls()) {
    for (const auto* f : {&options_.tls_cert_file, &options_.tls_key_file})
      if (!fs::is_regular_file(*f)) throw InputError(*f, "TLS file not found");
    auto ssl = std::make_unique<httplib::SSLServer>(options_.tls_cert_file.c_str(), options_.tls_key_file.c_str());
    if (!ssl->is_valid())
      throw InputError(options_.tls_cert_file, "the certificate or its key (" + options_.tls_key_file +
                                                   ") could not be loaded (PEM? matching pair?)");
    server_ = std::move(ssl);
    const int workers = std::max(2, options_.worker_threads);
    server_->new_task_queue = [workers] { return new httplib::ThreadPool(static_cast<std::size_t>(workers)); };
  } else {
    // A worker only for a request that has arrived whole: slow clients wait outside the pool.
    server_ = std::make_unique<server::GatedHttpServer>(static_cast<std::size_t>(std::max(2, options_.worker_threads)),
                                                        options_.read_timeout_s, options_.max_body_bytes);
  }
  // One request per connection: an idle keep-alive connection would hold a worker thread.
  server_->set_keep_alive_max_count(1);
  server_->set_read_timeout(options_.read_timeout_s, 0);
  server_->set_write_timeout(options_.read_timeout_s, 0);
  server_->set_payload_max_length(options_.max_body_bytes);
  // Before any body is read: a foreign Host (DNS rebinding), and a body cpp-httplib would read
  // whole whatever the limit (chunked, no length) or one over the limit.
  server_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    const std::string host = req.get_header_value("Host");
    if (!server::IsOwnHost(host, options_.host, options_.host_names)) {
      SendError(res, 403, "request: field 'Host': '" + host.substr(0, 200) +
                              "' is not a name of this server (DNS rebinding?): give it with --web-host-name");
      return httplib::Server::HandlerResponse::Handled;
    }
    if (const auto refusal = server::CheckBodyFraming(req, options_.max_body_bytes)) {
      SendError(res, refusal->status, refusal->message);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  // cpp-httplib 0.11 listens with a backlog of 5: a burst of browsers connecting at once (a shift
  // opening its pages) is then reset. The listening socket is captured here and Start() listens
  // again with the system's maximum (measured: bench/RESULTS.md, *Web front end*).
  server_->set_socket_options([this](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const char*>(&yes), sizeof yes);
    listen_socket_ = static_cast<int>(sock);
  });
  httplib::Headers headers = {
      {"Content-Security-Policy",
       "default-src 'self'; script-src 'self'; style-src 'self'; img-src 'self' data:; connect-src 'self'; "
       "object-src 'none'; base-uri 'none'; form-action 'self'; frame-ancestors 'none'"},
      {"X-Frame-Options", "DENY"},
      {"X-Content-Type-Options", "nosniff"},
      {"Referrer-Policy", "no-referrer"},
      {"Cross-Origin-Opener-Policy", "same-origin"},
      {"Cross-Origin-Resource-Policy", "same-origin"},
      {"Cache-Control", "no-store"},
  };
  if (tls()) headers.emplace("Strict-Transport-Security", "max-age=31536000");
  server_->set_default_headers(headers);
  Routes();
}

WebServer::~WebServer() { Stop(); }

void WebServer::LoadStaticFiles() {
  const fs::path dir(options_.static_dir);
  if (!fs::is_directory(dir)) throw InputError(options_.static_dir, "the web pages folder does not exist (--web-root)");
  // Only the files found here at start are ever served, by exact name: no path from a request
  // reaches the file system.
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file())
      static_files_["/" + entry.path().filename().string()] = {ContentTypeOf(entry.path()), ReadWholeFile(entry.path())};
  if (!fs::is_regular_file(options_.chartjs_file))
    throw InputError(options_.chartjs_file, "Chart.js not found: install Debian's libjs-chart.js (scripts/install-deps.sh)");
  static_files_["/vendor/chart.min.js"] = {"text/javascript; charset=utf-8", ReadWholeFile(options_.chartjs_file)};
}

void WebServer::ServeStatic(const httplib::Request& req, httplib::Response& res) const {
  auto it = static_files_.find(req.path);
  if (it == static_files_.end()) return SendError(res, 404, "no such page: " + req.path);
  res.headers.erase("Cache-Control");
  res.set_header("Cache-Control", "no-cache");
  res.set_content(it->second.bytes, it->second.content_type.c_str());
}

std::string WebServer::Url() const {
  return fmt::format("{}://{}:{}/", tls() ? "https" : "http", options_.host, port_);
}

void WebServer::Start() {
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.host);
    if (port_ <= 0) throw InputError("--web", "cannot listen on " + options_.host);
  } else {
    if (!server_->bind_to_port(options_.host, options_.port))
      throw InputError("--web", fmt::format("cannot listen on {}:{} (in use, or not an address of this computer)",
                                            options_.host, options_.port));
    port_ = options_.port;
  }
  if (listen_socket_ >= 0) ::listen(listen_socket_, SOMAXCONN);
  thread_ = std::thread([this] { server_->listen_after_bind(); });
}

void WebServer::Stop() {
  if (!thread_.joinable()) return;
  server_->stop();
  thread_.join();
  try {
    refusals_.Flush();
  } catch (const std::exception&) {  // the audit file went away: nothing left to do at stop
  }
}

void WebServer::HandleLogin(const httplib::Request& req, httplib::Response& res) {
  const std::string remote = Remote(req);
  AuditEntry audit;
  audit.remote = remote;
  audit.action = "login";
  try {
    CheckSameOrigin(req, tls());
    const json body = ParseBody(req);
    const std::string user = StringField(body, "user", 64);
    const std::string password = StringField(body, "password", 1024);
    audit.target = user;
    // The attempt is reserved before the password is hashed: parallel guesses count at once.
    LoginLimiter::Attempt attempt = limiter_.Reserve(user, req.remote_addr, SteadyNowS());
    if (!attempt.granted()) {
      using V = LoginLimiter::Verdict;
      const double wait = std::max(1.0, std::ceil(attempt.retry_after_s()));
      const std::string who = attempt.by_address() ? "address " + req.remote_addr : "user " + user;
      std::string error;
      switch (attempt.verdict()) {
        case V::kBusy:
          audit.outcome = "refused: busy checking other logins";
          error = "the server is busy checking other logins: try again in a second";
          break;
        case V::kPending:
          audit.outcome = "refused: other logins of this " + std::string(attempt.by_address() ? "address" : "name") +
                          " are being checked";
          error = audit.outcome.substr(9) + ": try again in a second";
          break;
        default:
          audit.outcome = "refused: locked out";
          error = fmt::format("too many failed logins: try again in {:.0f} s", wait);
      }
      // One audit row per burst with a count, not one per request.
      refusals_.Refused(attempt.verdict() == V::kBusy ? "busy " + req.remote_addr : audit.outcome + " " + who, audit,
                        UnixNowS());
      res.set_header("Retry-After", fmt::format("{:.0f}", wait));
      return SendJson(res, attempt.verdict() == V::kBusy ? 503 : 429, {{"error", error}, {"retry_after_s", wait}});
    }
    const auto record = access_.FindUser(user);
    // An unknown name costs the same hashing time as a wrong password (no user enumeration by timing).
    static const std::string dummy_hash = HashPassword(RandomToken(16));
    const bool ok = VerifyPassword(record ? record->password_hash : dummy_hash, password) && record;
    const double now = SteadyNowS();
    if (!ok) {
      attempt.Failed(now);
      audit.outcome = "failed: wrong user name or password";
      access_.Record(audit);
      return SendError(res, 401, "wrong user name or password");
    }
    attempt.Succeeded();
    const Session s = sessions_.Create(record->name, record->role, record->password_hash, now);
    std::string cookie = fmt::format("{}={}; Path=/; HttpOnly; SameSite=Strict", kCookieName, s.id);
    if (tls()) cookie += "; Secure";
    res.set_header("Set-Cookie", cookie);
    audit.user = s.user;
    audit.role = std::string(RoleName(s.role));
    audit.outcome = "ok";
    access_.Record(audit);
    SendJson(res, 200, {{"user", s.user}, {"role", RoleName(s.role)}, {"csrf", s.csrf_token}});
  } catch (const HttpError& e) {
    SendError(res, e.status, e.what());
  }
}

void WebServer::Routes() {
  auto& svr = *server_;
  using Handler = std::function<json(Call&)>;
  enum class Method { kGet, kPost };
  // One endpoint of the API: session, role, CSRF and same origin (POST), body, errors, audit.
  auto api = [this, &svr](Method method, const std::string& pattern, Role need, std::string action, Handler fn) {
    auto handler = [this, need, action, fn, method](const httplib::Request& req, httplib::Response& res) {
      std::optional<Session> session = sessions_.Touch(CookieValue(req, kCookieName), SteadyNowS());
      if (!session) return SendError(res, 401, "not logged in, or the session has expired");
      // The user database decides on every request: a removed user or a changed password ends the
      // session, a changed role applies at once.
      const auto user = access_.FindUser(session->user);
      if (!user || user->password_hash != session->password_hash) {
        sessions_.Remove(session->id);
        return SendError(res, 401, "the account was removed or its password changed: log in again");
      }
      session->role = user->role;
      AuditEntry audit;
      audit.user = session->user;
      audit.role = std::string(RoleName(session->role));
      audit.remote = Remote(req);
      Call call{req, res, *session, json::object(), req.path, "", false};
      int status = 200;
      std::string error;
      json answer;
      try {
        if (method == Method::kPost) {
          CheckSameOrigin(req, tls());
          if (!ConstantTimeEquals(req.get_header_value("X-CSRF-Token"), session->csrf_token))
            throw HttpError(403, "missing or wrong CSRF token (X-CSRF-Token)");
          call.body = ParseBody(req);
        }
        if (!HasRole(session->role, need))
          throw HttpError(403, fmt::format("this needs the {} role; you are {}", RoleName(need), RoleName(session->role)));
        answer = fn(call);
      } catch (const HttpError& e) {
        status = e.status, error = e.what();
      } catch (const BackendError& e) {
        status = e.status(), error = e.what();
      } catch (const InputError& e) {
        status = 400, error = e.what();
      } catch (const std::invalid_argument& e) {
        status = 400, error = e.what();
      } catch (const std::exception& e) {
        status = 500, error = std::string("internal error: ") + e.what();
      }
      if (!error.empty()) SendError(res, status, error);
      else if (!call.sent) SendJson(res, 200, answer);
      if (!action.empty() || (status == 403 && method == Method::kPost)) {
        audit.action = action.empty() ? "request" : action;
        audit.target = call.target;
        audit.detail = call.detail.empty() && !call.body.empty() ? call.body.dump() : call.detail;
        audit.outcome = error.empty() ? "ok" : fmt::format("{}: {}", status == 500 ? "failed" : "refused", error);
        try {
          access_.Record(audit);
        } catch (const std::exception& e) {
          SendError(res, 500, std::string("the operation ran but the audit log could not be written: ") + e.what());
        }
      }
    };
    if (method == Method::kGet) svr.Get(pattern, handler);
    else svr.Post(pattern, handler);
  };
  const std::string machine = std::string("/api/machines/") + kIdPattern;

  svr.Post("/api/login", [this](const httplib::Request& req, httplib::Response& res) { HandleLogin(req, res); });
  api(Method::kPost, "/api/logout", Role::kViewer, "logout", [this](Call& c) {
    sessions_.Remove(c.session.id);
    std::string cookie = fmt::format("{}=; Path=/; Max-Age=0; HttpOnly; SameSite=Strict", kCookieName);
    if (tls()) cookie += "; Secure";
    c.res.set_header("Set-Cookie", cookie);
    c.target = c.session.user;
    return json{{"ok", true}};
  });
  api(Method::kGet, "/api/session", Role::kViewer, "", [this](Call& c) {
    return json{{"user", c.session.user},
                {"role", RoleName(c.session.role)},
                {"csrf", c.session.csrf_token},
                {"idle_timeout_s", sessions_.timeouts().idle_timeout_s},
                {"absolute_timeout_s", sessions_.timeouts().absolute_timeout_s},
                {"backend", backend_.Describe()}};
  });
  api(Method::kGet, "/api/machines", Role::kViewer, "", [this](Call& c) {
    MachineQuery q;
    if (c.req.has_param("filter")) q.filter = c.req.get_param_value("filter").substr(0, 128);
    if (c.req.has_param("sort")) q.sort = c.req.get_param_value("sort");
    q.descending = c.req.get_param_value("order") == "desc";
    q.alarms_only = c.req.get_param_value("alarms") == "1";
    q.disconnected_only = c.req.get_param_value("disconnected") == "1";
    q.offset = ParamCount(c.req, "offset", 0, 1000000);
    q.limit = ParamCount(c.req, "limit", 200, 2000);
    const MachinePage page = ApplyQuery(backend_.ListMachines(), q);
    json list = json::array();
    for (const auto& m : page.machines) list.push_back(runtime::MachineViewJson(m));
    return json{{"total", page.total}, {"matched", page.matched}, {"offset", q.offset}, {"machines", list}};
  });
  api(Method::kGet, machine, Role::kViewer, "", [this](Call& c) { return ToJson(backend_.Machine(c.req.matches[1])); });
  api(Method::kGet, machine + "/live", Role::kViewer, "", [this](Call& c) {
    const auto after = static_cast<std::uint64_t>(ParamNumber(c.req, "after", 0));
    const std::size_t max = ParamCount(c.req, "max", options_.live_max_samples, options_.live_max_samples);
    return ToJson(backend_.Live(c.req.matches[1], after, max));
  });
  api(Method::kGet, machine + "/history", Role::kViewer, "", [this](Call& c) {
    const double to = ParamNumber(c.req, "to", 0), from = ParamNumber(c.req, "from", 0);
    if (!c.req.has_param("from") || !c.req.has_param("to")) throw HttpError(400, "history needs from and to (unix seconds)");
    if (!(from < to)) throw HttpError(400, "history: 'from' must be before 'to'");
    const std::size_t points = ParamCount(c.req, "points", 600, 5000);
    return ToJson(backend_.History(c.req.matches[1], from, to, points));
  });
  api(Method::kGet, machine + "/export", Role::kOperator, "export", [this](Call& c) {
    const double to = ParamNumber(c.req, "to", 0), from = ParamNumber(c.req, "from", 0);
    if (!c.req.has_param("from") || !c.req.has_param("to")) throw HttpError(400, "export needs from and to (unix seconds)");
    if (!(from < to)) throw HttpError(400, "export: 'from' must be before 'to'");
    const std::string format = c.req.get_param_value("format");
    const std::string table = c.req.has_param("table") ? c.req.get_param_value("table") : "temperature";
    ExportFormat f = ExportFormat::kXlsx;
    if (format == "csv" && table == "temperature") f = ExportFormat::kCsvTemperature;
    else if (format == "csv" && table == "compensation") f = ExportFormat::kCsvCompensation;
    else if (format != "xlsx")
      throw HttpError(400, "export: format must be csv (table temperature or compensation) or xlsx");
    ExportFile file = backend_.Export(c.req.matches[1], from, to, f);
    c.target = c.req.matches[1];
    c.detail = fmt::format("{} from {} to {} ({} bytes)", format, from, to, file.bytes.size());
    c.res.set_header("Content-Disposition", "attachment; filename=\"" + file.file_name + "\"");
    c.res.set_content(file.bytes, file.content_type.c_str());
    c.sent = true;
    return json();
  });
  api(Method::kPost, machine + "/axes/([A-Za-z0-9_]{1,16})", Role::kOperator, "axis_enable", [this](Call& c) {
    const bool on = BoolField(c.body, "enabled");
    c.target = std::string(c.req.matches[1]) + "/" + std::string(c.req.matches[2]);
    c.detail = on ? "enable" : "disable";
    backend_.SetAxisEnabled(c.who(), c.req.matches[1], c.req.matches[2], on);
    return json{{"ok", true}};
  });
  api(Method::kPost, machine + "/coolant", Role::kOperator, "coolant_override", [this](Call& c) {
    const std::string state = StringField(c.body, "state", 16);
    c.target = c.req.matches[1];
    c.detail = state.empty() ? "override cleared" : "override " + state;
    backend_.SetCoolantOverride(c.who(), c.req.matches[1], state);
    return json{{"ok", true}};
  });
  api(Method::kPost, machine + "/model", Role::kAdmin, "model_load", [this](Call& c) {
    const std::string revision = StringField(c.body, "revision", 64);
    c.target = c.req.matches[1];
    c.detail = "revision " + revision;
    backend_.LoadModelRevision(c.who(), c.req.matches[1], revision);
    return json{{"ok", true}, {"revision", revision}};
  });
  api(Method::kPost, machine + "/model/rollback", Role::kAdmin, "model_rollback", [this](Call& c) {
    c.target = c.req.matches[1];
    const std::string now = backend_.RollbackModel(c.who(), c.req.matches[1]);
    c.detail = "now revision " + now;
    return json{{"ok", true}, {"revision", now}};
  });
  api(Method::kGet, "/api/alarms", Role::kViewer, "", [this](Call& c) {
    json list = json::array();
    for (const auto& a : backend_.Alarms(ParamCount(c.req, "limit", 500, 5000))) list.push_back(ToJson(a));
    return json{{"alarms", list}};
  });
  api(Method::kPost, std::string("/api/alarms/") + "([A-Za-z0-9_.:\\-]{1,128})/ack", Role::kOperator, "alarm_ack",
      [this](Call& c) {
        c.target = c.req.matches[1];
        backend_.AcknowledgeAlarm(c.who(), c.req.matches[1]);
        return json{{"ok", true}};
      });
  api(Method::kGet, "/api/audit", Role::kAdmin, "", [this](Call& c) {
    json list = json::array();
    for (const auto& e : access_.RecentAudit(ParamCount(c.req, "limit", 200, 5000))) list.push_back(ToJson(e));
    return json{{"entries", list}};
  });

  svr.Get("/", [](const httplib::Request&, httplib::Response& res) { res.set_redirect("/overview.html"); });
  svr.Get(R"(/[A-Za-z0-9_.\-]+)", [this](const httplib::Request& req, httplib::Response& res) { ServeStatic(req, res); });
  svr.Get("/vendor/chart.min.js", [this](const httplib::Request& req, httplib::Response& res) { ServeStatic(req, res); });

  svr.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    const char* why = res.status == 404   ? "not found"
                      : res.status == 413 ? "the request body is too large"
                      : res.status == 405 ? "method not allowed"
                                          : "bad request";
    SendError(res, res.status, why);
    return httplib::Server::HandlerResponse::Handled;
  }));
  svr.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
    SendError(res, 500, "internal error");
  });
}

}  // namespace trueaxis::web
