#pragma once
// WebServer: the browser front end of seed 000's remote monitoring module (docs/web.md) on
// cpp-httplib. It serves the pages (static files read once at start, Chart.js from Debian's
// libjs-chart.js) and a JSON API over any MonitorBackend, behind a login:
//
//   POST /api/login → session cookie (HttpOnly, SameSite=Strict, Secure with TLS) + CSRF token
//   every /api call → session checked (idle + absolute timeout), role checked per endpoint,
//   every POST → CSRF token (X-CSRF-Token) and same-origin checked, every operation audited;
//   every request → Host checked (DNS rebinding), a body only with Content-Length within the limit
//   (server/http_guard.hpp, shared with the control API).
//
// Live values are fetched by short polling with a sequence number (`/live?after=N`): a viewer
// holds a worker thread only while its request runs and connections are closed after each
// response, so the number of viewers is bounded by memory and CPU, not by the worker pool
// (bench/RESULTS.md, *Web*: the SSE alternative measured).
#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/login_limiter.hpp"
#include "trueaxis/web/monitor_backend.hpp"
#include "trueaxis/web/refusal_audit.hpp"
#include "trueaxis/web/session_store.hpp"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace trueaxis::web {

struct WebServerOptions {
  std::string host = "127.0.0.1";  // loopback unless told otherwise
  std::vector<std::string> host_names;  // other names browsers reach this server by (Host header)
  int port = 8080;                 // 0: any free port (tests)
  std::string static_dir;          // the pages; "" = DefaultStaticDir()
  std::string chartjs_file = "/usr/share/javascript/chart.js/chart.min.js";  // Debian libjs-chart.js
  std::string tls_cert_file, tls_key_file;  // both or neither: HTTPS
  SessionTimeouts sessions;
  LoginLimits login;
  int worker_threads = 32;
  std::size_t max_body_bytes = 16 * 1024;
  int read_timeout_s = 5;
  std::size_t live_max_samples = 600;
};

// The folder of the pages: <program folder>/../share/trueaxis/web when installed, the source tree's
// src/web/static for a program run from its build tree (core/install_paths.hpp). Throws InputError
// naming --web-root and every place looked in when there is none.
std::string DefaultStaticDir();

class WebServer {
 public:
  // Reads the pages; throws InputError naming a missing folder, Chart.js file or bad certificate.
  WebServer(MonitorBackend& backend, AccessDb& access, WebServerOptions options);
  ~WebServer();  // Stop()
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Binds (throws InputError when the address is taken or invalid) and serves on its own thread.
  void Start();
  void Stop();
  int port() const { return port_; }
  bool tls() const { return !options_.tls_cert_file.empty(); }
  std::string Url() const;
  SessionStore& sessions() { return sessions_; }

 private:
  struct StaticFile {
    std::string content_type;
    std::string bytes;
  };
  struct Call;
  void LoadStaticFiles();
  void Routes();
  void ServeStatic(const httplib::Request& req, httplib::Response& res) const;
  void HandleLogin(const httplib::Request& req, httplib::Response& res);
  void HandleLogout(const httplib::Request& req, httplib::Response& res);

  MonitorBackend& backend_;
  AccessDb& access_;
  WebServerOptions options_;
  SessionStore sessions_;
  LoginLimiter limiter_;
  RefusalAudit refusals_;
  std::map<std::string, StaticFile> static_files_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  int port_ = 0;
  int listen_socket_ = -1;
};

}  // namespace trueaxis::web
