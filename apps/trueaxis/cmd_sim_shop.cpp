// trueaxis sim shop: N virtual machines, each behind its own MODBUS TCP
// terminal on base_port + i, served from one process and one epoll thread
// (sim::VirtualShop, docs/server.md), so a 1,000-machine shop runs on one box.
//
//   trueaxis sim shop --machines 100 --base-port 15000 --time-scale 60 --write-shop out/shop.toml --model out/demo/model.json
#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <thread>

#include <fmt/format.h>

#include "command.hpp"
#include "sim_command.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/core/install_paths.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/sim_shop/virtual_shop.hpp"

namespace {

using namespace trueaxis;

std::atomic<bool> g_stop{false};
extern "C" void OnShopStop(int) { g_stop.store(true); }

struct ShopOptions {
  sim::VirtualShopOptions shop;
  double duration_s = 0;
  double status_interval_s = 5;
  std::string write_shop, model, history = "shop.db";
  double period_s = 0.1;
  int http_port = 0;
};

void RunShop(ShopOptions o) {
  if (o.shop.machine_files.empty()) o.shop.machine_files = {trueaxis::DefaultExampleFile("machines/vmc850.toml")};
  g_stop.store(false);
  std::signal(SIGINT, OnShopStop);
  std::signal(SIGTERM, OnShopStop);
  cli::CheckSecondsOption(o.duration_s, "--duration-s", "until stopped");
  cli::CheckSecondsOption(o.status_interval_s, "--status-interval-s", "none");
  if (!o.write_shop.empty() && o.model.empty())
    throw InputError("command line", 0, "--model", "required with --write-shop: the model file every machine starts with");
  sim::VirtualShop shop(o.shop);  // InputError on a bad description or option
  const auto machines = shop.Machines();
  if (!o.write_shop.empty()) {
    const auto parent = std::filesystem::path(o.write_shop).parent_path();
    if (!parent.empty()) std::filesystem::create_directories(parent);
    // Paths in the shop file resolve against its folder: the model's is written absolute. Atomic: a server
    // started beside the shop never reads half a file.
    WriteTextFile(o.write_shop, sim::ShopFileFor(machines, o.shop.bind_address,
                                                    std::filesystem::absolute(o.model).lexically_normal().string(),
                                                    o.history, o.period_s, o.http_port));
  }
  std::string error;
  if (!shop.Start(&error)) {
    fmt::print(stderr, "trueaxis sim shop: {}\n", error);
    throw CLI::RuntimeError(cli::kExitFailure);
  }
  fmt::print("trueaxis sim shop: {} machines on {}:{}..{}, time x{}, watchdog {}{}\n", machines.size(),
             o.shop.bind_address, o.shop.base_port, o.shop.base_port + o.shop.machines - 1, o.shop.time_scale,
             o.shop.watchdog_s > 0 ? fmt::format("{} s", o.shop.watchdog_s) : "off",
             o.write_shop.empty() ? "" : fmt::format(", shop file {}", o.write_shop));
  std::fflush(stdout);
  const auto t0 = std::chrono::steady_clock::now();
  auto wall = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  double next_status = o.status_interval_s;
  auto line = [&] {
    const auto s = shop.Stats();
    fmt::print("[{:7.1f} s] {} requests ({} exceptions), {} compensation writes, {} connections, {} machine ticks, {} watchdog steps\n",
               wall(), s.requests, s.exceptions, s.compensation_writes, s.connections, s.ticks, s.watchdog_steps);
    std::fflush(stdout);
  };
  while (!g_stop.load() && (o.duration_s <= 0 || wall() < o.duration_s)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    if (o.status_interval_s > 0 && wall() >= next_status) {
      line();
      next_status += o.status_interval_s;
    }
  }
  shop.Stop();
  line();
}

void Setup(CLI::App& app) {
  auto o = std::make_shared<ShopOptions>();
  CLI::App* cmd = trueaxis::cli::SimCommand(app)->add_subcommand(
      "shop", "Serve N virtual machines, one MODBUS TCP terminal each on base-port + i, from one process (docs/server.md)");
  cmd->add_option("--machines", o->shop.machines, "Number of machines")->capture_default_str();
  cmd->add_option("--base-port,--port", o->shop.base_port, "Machine i listens on base-port + i")->capture_default_str();
  cmd->add_option("--machine-files", o->shop.machine_files, "Machine descriptions, used round robin (docs/machine-file.md; default: "
                  "examples/machines/vmc850.toml of the working folder, else of the installed examples)")
      ->delimiter(',')->check(CLI::ExistingFile);
  cmd->add_option("--bind", o->shop.bind_address, "IPv4 address to listen on")->capture_default_str();
  cmd->add_option("--time-scale", o->shop.time_scale, "Machine seconds per wall-clock second")->capture_default_str();
  cmd->add_option("--seed", o->shop.seed, "Seed of machine 0 (machine i: seed + i)")->capture_default_str();
  cmd->add_option("--tick-s", o->shop.tick_s, "Each machine is advanced and its registers refreshed this often")->capture_default_str();
  cmd->add_option("--day-s", o->shop.day_s, "Length of a machine's work / coolant / idle schedule (machine seconds)")->capture_default_str();
  cmd->add_option("--watchdog-s", o->shop.watchdog_s, "Ramp the compensation to 0 after this long without a client write (0: hold)")
      ->capture_default_str();
  cmd->add_option("--watchdog-ramp-um-per-s", o->shop.watchdog_ramp_um_per_s, "Rate of that ramp")->capture_default_str();
  cmd->add_option("--duration-s", o->duration_s, "Stop after this many wall-clock seconds (0: until Ctrl-C)")->capture_default_str();
  cmd->add_option("--status-interval-s", o->status_interval_s, "Wall seconds between status lines (0: none)")->capture_default_str();
  cmd->add_option("--write-shop", o->write_shop, "Write the shop file for `trueaxis server` to this path");
  cmd->add_option("--model", o->model, "Model file every machine of the written shop file starts with");
  cmd->add_option("--history", o->history, "history = ... of the written shop file")->capture_default_str();
  cmd->add_option("--period-s", o->period_s, "period_s of the written shop file")->capture_default_str();
  cmd->add_option("--http-port", o->http_port, "[http] port of the written shop file (0: none)")->capture_default_str();
  cmd->callback([o] { RunShop(*o); });
}

trueaxis::cli::CommandRegistrar reg("sim_shop", Setup);

}  // namespace
