// trueaxis server: the workshop server (seed 003, docs/server.md). Polls every
// machine's terminal over MODBUS TCP from event loops, runs each machine's
// compensator (the same step as `run`), writes the corrections back, records
// the shop's history and serves the JSON control API.
//
//   trueaxis server --config shop.toml [--duration-s S] [--web HOST:PORT --users FILE]
//   trueaxis server status --url http://127.0.0.1:8650 [--json]
//   trueaxis server model load --url ... --machine M --file model.json --user alice
//   trueaxis server model rollback --url ... --machine M --user alice
#include <atomic>
#include <algorithm>
#include <chrono>
#include <csignal>
#include <malloc.h>
#include <filesystem>
#include <memory>
#include <regex>
#include <thread>

#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "command.hpp"
#include "optional_features.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/http_api.hpp"
#include "trueaxis/server/mtconnect_agent.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/server/shop_config.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/store/open_history_sink.hpp"
#include "trueaxis/web/shop_backend.hpp"
#include "web_front_end.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop{false};
extern "C" void OnServerStop(int) { g_stop.store(true); }

struct ServerOptions {
  std::string config;
  double duration_s = 0;
  double status_interval_s = 5;
  int http_port = -1;  // the shop file's unless --http-port is given
  bool http_port_given = false;
  int poll_threads = 1;  // the shop file's [server] poll_threads unless --poll-threads is given
  bool poll_threads_given = false;
  bool quiet = false;
  cli::WebCliOptions web;  // the browser front end over the whole shop (docs/web.md)
  std::string mtconnect;   // HOST:PORT of the MTConnect agent ("" none)
  server::MtconnectOptions mtconnect_options;
};

std::string Summary(const server::Shop& shop, double wall_s, double since_s, std::uint64_t cycles_before) {
  const auto snap = shop.Snapshot();
  std::size_t connected = 0, alarmed = 0;
  for (const auto& m : snap) {
    connected += m.connected ? 1 : 0;
    alarmed += m.alarms ? 1 : 0;
  }
  const auto st = shop.Stats();
  const double rate = since_s > 0 ? static_cast<double>(st.complete_cycles - cycles_before) / since_s : 0;
  return fmt::format("[{:7.1f} s] {}/{} machines connected, {} with alarms | {:.0f} complete cycles/s | read->write p50 {:.2f} "
                     "p99 {:.2f} max {:.2f} ms | {} faults, {} overruns",
                     wall_s, connected, snap.size(), alarmed, rate, st.latency_p50_ms, st.latency_p99_ms, st.latency_max_ms,
                     st.faults, st.overruns);
}

// --mtconnect [HOST:]PORT, 127.0.0.1 when no host is given (port 0: any free one, printed at start).
server::MtconnectOptions MtconnectListen(const std::string& listen, server::MtconnectOptions o) {
  static const std::regex form(R"((?:(.+):)?([0-9]{1,5}))");
  std::smatch m;
  if (!std::regex_match(listen, m, form) || std::stoi(m[2].str()) > 65535)
    throw InputError("command line", 0, "--mtconnect", "'" + listen + "' is not [HOST:]PORT (e.g. 127.0.0.1:5000)");
  if (m[1].matched) o.bind = m[1].str();
  if (o.bind.size() > 2 && o.bind.front() == '[' && o.bind.back() == ']') o.bind = o.bind.substr(1, o.bind.size() - 2);
  o.port = std::stoi(m[2].str());
  return o;
}

void RunServer(const ServerOptions& o) {
  // Two malloc arenas for the whole process: the HTTP workers' large, short-lived answers (the JSON of
  // every machine) are then reused instead of each worker's arena keeping its own (tens of MB in a
  // thousand-machine shop); the event loop allocates nothing per cycle, so it meets no contention.
  mallopt(M_ARENA_MAX, 2);
  // Blocks from 256 kB up (such an answer's text) are mapped and returned to the system when freed;
  // without a fixed threshold glibc raises it to the largest block freed, and each answer's
  // megabytes then stay in the process.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  g_stop.store(false);
  std::signal(SIGINT, OnServerStop);
  std::signal(SIGTERM, OnServerStop);
  cli::CheckSecondsOption(o.duration_s, "--duration-s", "until stopped");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "none");
  if (o.http_port_given && (o.http_port < 0 || o.http_port > 65535))
    throw InputError("command line", 0, "--http-port", fmt::format("{} is out of range: 1 to 65535 (0: no API)", o.http_port));
  const server::MtconnectOptions mtc = o.mtconnect.empty() ? o.mtconnect_options : MtconnectListen(o.mtconnect, o.mtconnect_options);
  if (!o.mtconnect.empty()) server::CheckMtconnectOptions(mtc);
  server::ShopConfig config = server::ReadShopConfig(o.config);  // InputError: file, line, field
  if (o.http_port_given) config.http_port = o.http_port;
  if (o.poll_threads_given) {
    if (o.poll_threads < 1 || o.poll_threads > server::kMaxPollThreads)
      throw InputError("command line", 0, "--poll-threads",
                       fmt::format("{} is out of range: 1 to {} polling threads", o.poll_threads, server::kMaxPollThreads));
    config.poll_threads = o.poll_threads;
  }
  // Another server on the port, or a bind address that is not this computer's: say which setting.
  auto http_error = [&](const std::string& error) {
    if (o.http_port_given) return InputError("command line", 0, "--http-port", error);
    const bool bad_bind = !server::CanListen(config.http_bind, 0, nullptr);  // not even any port: the address
    return InputError(config.source, bad_bind ? config.http_bind_line : config.http_port_line, bad_bind ? "http.bind" : "http.port",
                      error);
  };
  if (std::string error; config.http_port > 0 && !server::CanListen(config.http_bind, config.http_port, &error))
    throw http_error(error);  // before the history is opened: a refused server records nothing
  if (std::string error; !o.mtconnect.empty() && !server::CanListen(mtc.bind, mtc.port, &error))
    throw InputError("command line", 0, "--mtconnect", error);
  std::unique_ptr<store::HistoryWriter> history;
  if (!config.history.empty()) {
    const auto parent = std::filesystem::path(config.history).parent_path();
    if (!store::IsPostgresUrl(config.history) && !parent.empty()) std::filesystem::create_directories(parent);
    store::HistoryWriterOptions ho;
    // Two seconds of the shop's records (one per axis and channel per record_interval_s) for a slow
    // disk, at least 16384: the queue's memory grows with the shop, not 78 MB for any shop.
    double records_per_s = 0;
    for (const auto& m : config.machines) records_per_s += static_cast<double>(m.axes.size() + m.channels.size());
    ho.queue_capacity = std::max<std::size_t>(16384, static_cast<std::size_t>(2.0 * records_per_s / config.record_interval_s));
    // A SQLite file, or a PostgreSQL server named by URL when one box is not enough (docs/server.md).
    history = std::make_unique<store::HistoryWriter>(store::OpenHistorySink(config.history), ho);
  }
  server::Shop shop(config, history.get());  // InputError: a model that does not fit its machine
  std::unique_ptr<server::HttpApi> api;
  if (config.http_port > 0) {
    api = std::make_unique<server::HttpApi>(shop, config.http_bind, config.http_port);
    std::string error;
    if (!api->Start(&error)) throw http_error(error);
    if (!server::IsLoopbackAddress(config.http_bind)) {
      const std::string warning = fmt::format(
          "the HTTP control API (no authentication: it loads models and switches compensation) listens on {}:{}, not "
          "on loopback: every computer that reaches this address can drive it ({}:{}: [http] bind)",
          config.http_bind, api->port(), config.source, config.http_bind_line);
      fmt::print(stderr, "warning: {}\n", warning);
      if (history)
        history->PushAlarm(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(), "warning",
                           "server", warning);
    }
  }
  std::unique_ptr<web::ShopBackend> web_backend;
  cli::WebFrontEnd web_front_end;
  if (!o.web.listen.empty()) {
    web::ShopBackendOptions wo;
    if (history && store::IsPostgresUrl(config.history))
      fmt::print(stderr, "warning: the web page's history and export read a SQLite history only; {} is not shown there\n",
                 history->path());
    else
      wo.history_db = config.history;
    web_backend = std::make_unique<web::ShopBackend>(shop, history.get(), wo);
    web_front_end = cli::StartWebFrontEnd(o.web, *web_backend);  // InputError: no user, bad address or certificate
  }
  std::unique_ptr<cli::LiveRelay> mqtt;
  if (!config.mqtt.broker.empty()) mqtt = cli::MakeShopMqttRelay(shop, config.mqtt);  // InputError, FeatureMissing
  std::unique_ptr<server::MtconnectAgent> mtconnect;
  if (!o.mtconnect.empty()) mtconnect = std::make_unique<server::MtconnectAgent>(shop, mtc);  // InputError: options out of range
  if (std::string error; mtconnect && !mtconnect->Start(&error)) throw InputError("command line", 0, "--mtconnect", error);
  shop.Start();
  if (web_backend) web_backend->Start();
  if (mqtt) mqtt->Start();
  fmt::print("trueaxis server: {} machines from {}, history {}{}{}\n", config.machines.size(), config.source,
             history ? history->path() : "off",
             api ? fmt::format(", API http://{}:{}/api/machines", config.http_bind, api->port()) : "",
             mqtt ? fmt::format(", MQTT {} ({}/{}/…)", config.mqtt.broker, config.mqtt.topic_root, config.mqtt.shop) : "");
  if (mtconnect) fmt::print("MTConnect agent: http://{}:{}/probe\n", mtc.bind, mtconnect->port());
  if (mtconnect && !server::IsLoopbackAddress(mtc.bind))
    fmt::print(stderr, "note: the MTConnect agent (read only, no authentication) listens on {}:{}: every computer that reaches "
               "this address reads the machines' values\n", mtc.bind, mtconnect->port());
  std::fflush(stdout);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  double next_status = o.status_interval_s, last_status = 0;
  std::uint64_t last_cycles = 0;
  // Not a core::PeriodicThread: the main thread watches the flag SIGINT/SIGTERM set (a signal
  // handler can set an atomic, not wake a thread), so it looks every 20 ms; the status lines keep
  // their own grid (next_status += interval: no drift).
  while (!g_stop.load() && (o.duration_s <= 0 || wall() < o.duration_s)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (!o.quiet && o.status_interval_s > 0 && wall() >= next_status) {
      fmt::print("{}\n", Summary(shop, wall(), wall() - last_status, last_cycles));
      std::fflush(stdout);
      last_cycles = shop.Stats().complete_cycles;
      last_status = wall();
      next_status += o.status_interval_s;
    }
  }
  if (web_front_end.server) web_front_end.server->Stop();
  if (web_backend) web_backend->Stop();
  if (mqtt) {
    mqtt->Stop();
    fmt::print("mqtt: {} ({})\n", config.mqtt.broker, mqtt->StatsReport());
  }
  if (api) api->Stop();
  if (mtconnect) mtconnect->Stop();
  shop.Stop();
  fmt::print("{}\n", Summary(shop, wall(), wall(), 0));
  for (const auto& m : shop.Snapshot()) {
    std::string axes;
    for (const auto& a : m.axes)
      axes += fmt::format(" {} {}", a.name, a.applied_um ? fmt::format("{:+.1f} um", *a.applied_um) : "UNAVAILABLE");
    if (m.name == shop.Snapshot().front().name || m.alarms || !m.connected)
      fmt::print("  {} {} | model rev {} | applied{} | alarms {}{}\n", m.name, m.connected ? "connected" : "DOWN",
                 m.model.revision, axes, m.alarm_names.empty() ? "none" : m.alarm_names,
                 m.last_fault.empty() ? "" : " | last fault: " + m.last_fault);
  }
  if (history) {
    history->Close();
    fmt::print("history: {} ({})\n", history->path(), history->Stats().BriefReport());
  }
}

// ---- the CLI against a running server ----

// --url: http://HOST[:PORT] (a bad URL is bad input, exit 2; a server that does not answer is not, exit 1).
void CheckUrl(const std::string& url) {
  static const std::regex form(R"(https?://([A-Za-z0-9._\-]+|\[[0-9A-Fa-f:.]+\])(:([0-9]{1,5}))?/?)");
  std::smatch m;
  if (!std::regex_match(url, m, form) || (m[3].matched && (std::stoi(m[3].str()) < 1 || std::stoi(m[3].str()) > 65535)))
    throw InputError("command line", 0, "--url", "'" + url + "' is not a server URL such as http://127.0.0.1:8650");
}

httplib::Result Call(const std::string& url, const std::string& method, const std::string& path, const nlohmann::json& body) {
  CheckUrl(url);
  std::unique_ptr<httplib::Client> client;
  try {
    client = std::make_unique<httplib::Client>(url);
  } catch (const std::exception&) {  // a scheme this build does not speak (https without TLS support)
    throw InputError("command line", 0, "--url", "'" + url + "': this scheme is not supported here (use http://)");
  }
  client->set_connection_timeout(2);
  client->set_read_timeout(5);
  auto res = method == "GET" ? client->Get(path.c_str()) : client->Post(path.c_str(), body.dump(), "application/json");
  if (!res) {
    const std::string why = res.error() == httplib::Error::Connection ? "no server answers there (is `trueaxis server` running "
                                                                        "with its [http] port?)"
                                                                      : httplib::to_string(res.error());
    fmt::print(stderr, "trueaxis server: cannot reach {}: {}\n", url, why);
    throw CLI::RuntimeError(cli::kExitFailure);  // not bad input: exit 1
  }
  return res;
}

void PrintOrFail(const httplib::Result& res) {
  if (res->status == 200) {
    fmt::print("{}", res->body);
    return;
  }
  std::string why = res->body;
  try {
    why = nlohmann::json::parse(res->body).value("error", res->body);
  } catch (...) {
  }
  fmt::print(stderr, "trueaxis server: HTTP {}: {}\n", res->status, why);
  throw CLI::RuntimeError(res->status == 404 || res->status == 400 || res->status == 422 ? cli::kExitBadInput : cli::kExitFailure);
}

void PrintStatus(const std::string& url, bool json) {
  auto res = Call(url, "GET", "/api/machines", nullptr);
  if (json || res->status != 200) return PrintOrFail(res);
  for (const auto& m : nlohmann::json::parse(res->body)) {
    std::string axes;
    for (const auto& a : m["axes"]) {
      // The axis's compensation state when it is not the model with its own sensors.
      const std::string state = a.value("state", std::string("full"));
      axes += fmt::format(" {} {}{}", a["name"].get<std::string>(),
                          a["applied_um"].is_null() ? "UNAVAILABLE" : fmt::format("{:+.1f} um", a["applied_um"].get<double>()),
                          state == "full" || state == "link_lost" ? "" : " (" + state + ")");
    }
    std::string alarms;
    for (const auto& name : m["alarms"]) alarms += (alarms.empty() ? "" : "|") + name.get<std::string>();
    fmt::print("{:<12} {:<9} model rev {} | applied{} | alarms {}\n", m["name"].get<std::string>(),
               m["connected"].get<bool>() ? "connected" : "DOWN", m["model"]["revision"].get<std::string>(), axes,
               alarms.empty() ? "none" : alarms);
  }
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<ServerOptions>();
  CLI::App* cmd = app.add_subcommand("server", "The workshop server: poll every machine's terminal, compensate, record (docs/server.md)");
  cmd->add_option("--config", o->config, "Shop file (TOML, docs/server.md)")->check(CLI::ExistingFile);
  cmd->add_option("--duration-s", o->duration_s, "Stop after this many seconds (0: until Ctrl-C / SIGTERM)")->capture_default_str();
  cmd->add_option("--status-interval-s", o->status_interval_s, "Seconds between status lines (0: none)")->capture_default_str();
  CLI::Option* http_port =
      cmd->add_option("--http-port", o->http_port, "HTTP control API port 1..65535, overriding the shop file's [http] port (0: off)");
  CLI::Option* poll_threads = cmd->add_option("--poll-threads", o->poll_threads,
                  fmt::format("Threads that poll the terminals (1 to {}), overriding the shop file's [server] poll_threads",
                              server::kMaxPollThreads));
  cmd->add_flag("--quiet", o->quiet, "No status lines");
  cli::AddWebOptions(cmd, o->web, "--web");
  cmd->add_option("--mtconnect", o->mtconnect,
                  "Serve every machine as an MTConnect 1.3 agent (/probe, /current, /sample) on [HOST:]PORT (host 127.0.0.1 unless given)");
  cmd->add_option("--mtconnect-period-s", o->mtconnect_options.period_s, "How often the MTConnect agent takes the shop's values")
      ->capture_default_str();
  cmd->add_option("--mtconnect-buffer", o->mtconnect_options.buffer_size, "Observations the MTConnect agent holds (bufferSize)")
      ->capture_default_str();
  cmd->add_option("--mtconnect-host-name", o->mtconnect_options.host_names,
                  "A name dashboards use for this computer, besides its host name and addresses (repeatable)");
  cmd->require_subcommand(0, 1);

  auto url = std::make_shared<std::string>("http://127.0.0.1:8650");
  auto json = std::make_shared<bool>(false);
  CLI::App* status = cmd->add_subcommand("status", "Status of every machine of a running server");
  status->add_option("--url", *url, "The server's HTTP API")->capture_default_str();
  status->add_flag("--json", *json, "The API's JSON as is");
  status->callback([url, json] { PrintStatus(*url, *json); });

  CLI::App* model = cmd->add_subcommand("model", "Change a machine's model on a running server");
  model->require_subcommand(1);
  auto machine = std::make_shared<std::string>();
  auto file = std::make_shared<std::string>();
  auto user = std::make_shared<std::string>();
  CLI::App* load = model->add_subcommand("load", "Load / replace the machine's model (ramps through the limiter)");
  load->add_option("--url", *url, "The server's HTTP API")->capture_default_str();
  load->add_option("--machine", *machine, "Machine name")->required();
  load->add_option("--file", *file, "Model file (a path on the server)")->required();
  load->add_option("--user", *user, "Who makes the change (recorded)")->required();
  load->callback([url, machine, file, user] {
    const std::string path = std::filesystem::absolute(*file).lexically_normal().string();
    PrintOrFail(Call(*url, "POST", "/api/machines/" + *machine + "/model", {{"file", path}, {"user", *user}}));
  });
  CLI::App* rollback = model->add_subcommand("rollback", "Go back to the machine's previous model");
  rollback->add_option("--url", *url, "The server's HTTP API")->capture_default_str();
  rollback->add_option("--machine", *machine, "Machine name")->required();
  rollback->add_option("--user", *user, "Who makes the change (recorded)")->required();
  rollback->callback([url, machine, user] {
    PrintOrFail(Call(*url, "POST", "/api/machines/" + *machine + "/rollback", {{"user", *user}}));
  });

  cmd->callback([o, cmd, http_port, poll_threads] {
    if (!cmd->get_subcommands().empty()) return;  // status / model ran
    if (o->config.empty()) throw InputError("command line", 0, "--config", "missing (required): the shop file");
    o->http_port_given = http_port->count() > 0;
    o->poll_threads_given = poll_threads->count() > 0;
    RunServer(*o);
  });
}

trueaxis::cli::CommandRegistrar reg("server", Setup);

}  // namespace
