#pragma once
// HttpApi: the shop's JSON control API over HTTP (cpp-httplib), bound to
// 127.0.0.1 by default — the CLI (`trueaxis server status|model ...`) and the
// web front end use it. Endpoints and payloads: docs/server.md.
//
//   GET  /api/machines                       every machine's status
//   GET  /api/machines/{name}                one machine
//   GET  /api/machines/{name}/models         its model changes (who, when, old → new)
//   POST /api/machines/{name}/model          {"file": "...", "user": "..."}   load / replace
//   POST /api/machines/{name}/rollback       {"user": "..."}
//   POST /api/machines/{name}/axes/{axis}    {"enabled": true|false, "user": "..."}
//   POST /api/machines/{name}/acknowledge    {"user": "..."}
//   POST /api/machines/{name}/coolant        {"override": "flood"|null, "user": "..."}
//   GET  /api/stats                          poll rate, latency, faults
// Errors: always {"error": "..."}: 400 bad or missing field, 404 unknown machine / axis / path,
// 405 wrong method, 413 body over 64 KiB, 415 a POST that is not application/json, 403 a request
// from another origin (a web page), 422 a model that does not fit or a field that is too long.
#include <memory>
#include <string>

#include <nlohmann/json.hpp>

#include "trueaxis/runtime/machine_view.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {

// A shop machine in the one vocabulary of both HTTP servers (runtime::MachineView; the web front
// end's ShopBackend shows the same): id = name, UNAVAILABLE values NaN.
runtime::MachineView MachineViewOf(const MachineStatus& status);
runtime::MachineModelView ModelViewOf(const ModelInfo& model);
// runtime::MachineViewJson of MachineViewOf, plus what only the server knows: the terminal's
// endpoint, its link counters and latency, the alarm bits and the unacknowledged alarms, the
// model's slot. UNAVAILABLE values are JSON null.
nlohmann::json ToJson(const MachineStatus& status);
nlohmann::json ToJson(const ModelChange& change);
nlohmann::json ToJson(const ShopStats& stats);

// 127.0.0.0/8, ::1 or "localhost": the control API has no authentication and warns on anything else.
bool IsLoopbackAddress(const std::string& address);

// Whether bind_address:port can be listened on now (SO_REUSEADDR only, as HttpApi): checked before
// the shop opens its history, so a second server on a port in use records nothing.
bool CanListen(const std::string& bind_address, int port, std::string* error);

class HttpApi {
 public:
  HttpApi(Shop& shop, std::string bind_address, int port);
  ~HttpApi();  // Stop()
  bool Start(std::string* error);  // port 0: any free port (see port())
  void Stop();
  int port() const { return port_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string bind_;
  int port_;
};

}  // namespace trueaxis::server
