// trueaxis web --listen 127.0.0.1:8080 --users FILE [--machines N] [--duration-s S]
// The web front end over the demo shop: N synthetic machines (web::SyntheticShop) with live
// values, history, alarms and models, until SIGINT/SIGTERM or the duration (docs/web.md). One
// real machine is served by `trueaxis run --web …`.
#include <atomic>
#include <chrono>
#include <csignal>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/web/synthetic_shop.hpp"
#include "web_front_end.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop{false};
extern "C" void WebCommandOnStopSignal(int) { g_stop.store(true); }

struct Options {
  cli::WebCliOptions web = [] {
    cli::WebCliOptions w;
    w.listen = "127.0.0.1:8080";
    return w;
  }();
  int machines = 200;
  double duration_s = 0;
  double period_s = 1.0;
};

void Run(const Options& o) {
  cli::CheckSecondsOption(o.duration_s, "--duration-s", "until SIGINT/SIGTERM");
  if (o.machines < 1 || o.machines > 100000) throw InputError("--machines", 0, "machines", "must be 1 to 100000");
  if (!(o.period_s >= 0.05)) throw InputError("--period-s", 0, "period", "must be at least 0.05 s");
  web::SyntheticShop shop(static_cast<std::size_t>(o.machines));
  shop.Start(o.period_s);
  cli::WebFrontEnd fe = cli::StartWebFrontEnd(o.web, shop);
  g_stop = false;
  std::signal(SIGINT, WebCommandOnStopSignal);
  std::signal(SIGTERM, WebCommandOnStopSignal);
  const auto t0 = std::chrono::steady_clock::now();
  while (!g_stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (o.duration_s > 0 && std::chrono::steady_clock::now() - t0 >= std::chrono::duration<double>(o.duration_s)) break;
  }
  fe.server->Stop();
  shop.Stop();
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  fmt::print("web: stopped ({} sessions open)\n", fe.server->sessions().Count());
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* cmd = app.add_subcommand("web", "Serve the web front end over the demo shop of synthetic machines");
  cli::AddWebOptions(cmd, o->web, "--listen");
  cmd->add_option("--machines", o->machines, "Synthetic machines in the shop")->capture_default_str();
  cmd->add_option("--period-s", o->period_s, "Live value interval")->capture_default_str();
  cmd->add_option("--duration-s", o->duration_s, "Stop after this many seconds (0: until SIGINT/SIGTERM)");
  cmd->callback([o] { Run(*o); });
}

trueaxis::cli::CommandRegistrar reg("web", Setup);

}  // namespace
