#pragma once
// The web front end's command-line options, shared by `trueaxis run --web …` (one machine) and
// `trueaxis web` (the demo shop), and starting it over a backend (docs/web.md).
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/monitor_backend.hpp"
#include "trueaxis/web/web_server.hpp"

namespace trueaxis::cli {

struct WebCliOptions {
  std::string listen;      // HOST:PORT; "" = no web front end
  std::string users;       // the user + audit database (trueaxis user add)
  std::string cert, key;   // TLS (PEM)
  std::string root;        // the pages folder ("" = web::DefaultStaticDir())
  std::vector<std::string> host_names;  // names browsers use for this server (Host header check)
  double idle_timeout_s = 15 * 60;
  double absolute_timeout_s = 8 * 3600;
};

// Adds --web/--listen (name given), --users, --web-cert, --web-key, --web-root, --web-host-name,
// --web-idle-timeout-s, --web-absolute-timeout-s.
void AddWebOptions(CLI::App* cmd, WebCliOptions& o, const std::string& listen_flag);

struct WebFrontEnd {
  std::unique_ptr<web::AccessDb> access;
  std::unique_ptr<web::WebServer> server;
};
// Opens the user database (refused when it holds no user: no default password), binds, serves.
// Throws InputError naming the option at fault.
WebFrontEnd StartWebFrontEnd(const WebCliOptions& o, web::MonitorBackend& backend);

}  // namespace trueaxis::cli
