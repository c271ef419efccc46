#include "web_front_end.hpp"

#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::cli {

void AddWebOptions(CLI::App* cmd, WebCliOptions& o, const std::string& listen_flag) {
  cmd->add_option(listen_flag, o.listen,
                  "Serve the web front end on HOST:PORT (e.g. 127.0.0.1:8080; loopback unless you name another address)");
  cmd->add_option("--users", o.users, "User and audit-log database (SQLite; `trueaxis user add` makes the first admin)");
  cmd->add_option("--web-cert", o.cert, "TLS certificate (PEM): serve HTTPS (docs/web.md says how to make one)");
  cmd->add_option("--web-key", o.key, "TLS private key (PEM) of --web-cert");
  cmd->add_option("--web-host-name", o.host_names,
                  "A name browsers use for this server (DNS name; repeatable): other names in the Host header are "
                  "refused (DNS rebinding). IP addresses, localhost and this computer's host name need none");
  cmd->add_option("--web-root", o.root, "Folder of the pages (default: share/trueaxis/web next to the program's bin folder)");
  cmd->add_option("--web-idle-timeout-s", o.idle_timeout_s, "Log out after this long without a request")->capture_default_str();
  cmd->add_option("--web-absolute-timeout-s", o.absolute_timeout_s, "Log out this long after login")->capture_default_str();
}

WebFrontEnd StartWebFrontEnd(const WebCliOptions& o, web::MonitorBackend& backend) {
  WebFrontEnd fe;
  web::WebServerOptions so;
  const auto colon = o.listen.rfind(':');
  if (colon == std::string::npos || colon == 0)
    throw InputError("--web", 0, "listen", "'" + o.listen + "' is not HOST:PORT (e.g. 127.0.0.1:8080)");
  so.host = o.listen.substr(0, colon);
  try {
    std::size_t used = 0;
    so.port = std::stoi(o.listen.substr(colon + 1), &used);
    if (used != o.listen.size() - colon - 1 || so.port < 0 || so.port > 65535) throw std::out_of_range("");
  } catch (const std::exception&) {
    throw InputError("--web", 0, "listen", "'" + o.listen + "': the port must be 0 to 65535");
  }
  if (o.users.empty()) throw InputError("--users", 0, "users", "the web front end needs a user database (--users FILE)");
  if (!(o.idle_timeout_s > 0) || !(o.absolute_timeout_s > 0))
    throw InputError("--web-idle-timeout-s", 0, "timeout", "timeouts must be positive");
  fe.access = std::make_unique<web::AccessDb>(o.users);
  if (fe.access->Users().empty())
    throw InputError(o.users, 0, "users",
                     "holds no user yet: add the first admin with `trueaxis user add --users " + o.users +
                         " --name NAME --role admin` (there is no default password)");
  so.static_dir = o.root;
  so.host_names = o.host_names;
  so.tls_cert_file = o.cert;
  so.tls_key_file = o.key;
  so.sessions.idle_timeout_s = o.idle_timeout_s;
  so.sessions.absolute_timeout_s = o.absolute_timeout_s;
  const bool loopback = so.host == "127.0.0.1" || so.host == "localhost" || so.host == "::1";
  if (!loopback && o.cert.empty())
    fmt::print(stderr, "warning: serving {} without TLS: passwords and cookies cross the network in clear "
                       "(give --web-cert/--web-key)\n", so.host);
  fe.server = std::make_unique<web::WebServer>(backend, *fe.access, so);
  fe.server->Start();
  fmt::print(stderr, "web: {} ({}; users in {})\n", fe.server->Url(), backend.Describe(), o.users);
  return fe;
}

}  // namespace trueaxis::cli
