#pragma once
// Shared pieces of the server tests: a model for the VMC-850's sensors, a
// virtual shop on free ports of 127.0.0.1, a shop file for it, and waiting
// on a condition (never a fixed sleep as the assertion).
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>
#include <unistd.h>

#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/server/shop_config.hpp"
#include "trueaxis/sim_shop/virtual_shop.hpp"

namespace trueaxis::server::testing {

using sim::ShopFileFor;
using sim::TerminalFault;
using sim::VirtualShop;
using sim::VirtualShopOptions;
using sim::VirtualMachineInfo;

// A fresh scratch folder, removed when the test program exits (a failed test's folder stays while it runs).
inline std::string TempDir(const std::string& name) {
  struct RemovedAtExit {
    std::vector<std::filesystem::path> dirs;
    ~RemovedAtExit() {
      std::error_code ignored;
      for (const auto& d : dirs) std::filesystem::remove_all(d, ignored);
    }
  };
  static RemovedAtExit scratch;
  const auto dir = std::filesystem::temp_directory_path() / ("trueaxis_server_" + name + "_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  scratch.dirs.push_back(dir);
  return dir.string();
}

// A model over the VMC-850's sensors whose correction is tens of µm (so ramps are visible).
inline std::string WriteModel(const std::string& path, double scale = 1.0, const std::string& key_sensor_suffix = "_nut") {
  model::CompositeModel m;
  m.machine = "VMC-850";
  m.revision = scale > 1.5 ? 2 : 1;
  for (const char* axis : {"X", "Y", "Z"}) {
    model::AxisModel a;
    a.axis = axis;
    const std::string p(1, static_cast<char>(std::tolower(axis[0])));
    a.key_sensors = {p + key_sensor_suffix};
    a.baseline_temp_c = {20};
    a.ambient_sensor = "ambient";
    a.ambient_baseline_c = 20;
    for (int d = 0; d < 2; ++d) {
      auto& dm = a.directions[d];
      dm.geometric.center_mm = 300;
      dm.geometric.half_span_mm = 300;
      dm.geometric.coefficients_um = {scale * 30.0, scale * 5.0};
    }
    m.axes.push_back(a);
  }
  model::WriteModelFile(m, path);
  return path;
}

inline bool WaitFor(const std::function<bool()>& done, double limit_s = 10) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(limit_s);
  while (std::chrono::steady_clock::now() < end) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return done();
}

// Until every machine of a running shop is connected and has read its temperatures.
template <class ShopT>
bool WaitUntilEveryMachineReads(const ShopT& shop, double limit_s = 10) {
  return WaitFor(
      [&] {
        for (const auto& m : shop.Snapshot())
          if (!m.connected || m.channels.empty() || !m.channels[0].temp_c) return false;
        return true;
      },
      limit_s);
}

// A virtual shop of `n` VMC-850s on free ports.
inline std::unique_ptr<VirtualShop> StartVirtualShop(int n, VirtualShopOptions o = {}) {
  o.machine_files = {std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml"};
  o.machines = n;
  std::mt19937 rng(static_cast<unsigned>(getpid()) * 2654435761u + static_cast<unsigned>(n));
  for (int attempt = 0; attempt < 30; ++attempt) {
    o.base_port = 20000 + static_cast<int>(rng() % 40000);
    auto shop = std::make_unique<VirtualShop>(o);
    if (shop->Start(nullptr)) return shop;
  }
  return nullptr;
}

inline ShopConfig ConfigFor(const VirtualShop& shop, const std::string& model, double period_s = 0.05) {
  ShopConfig c = ParseShopConfig(ShopFileFor(shop.Machines(), "127.0.0.1", model, "", period_s, 0), "test-shop.toml");
  for (auto& m : c.machines) {
    m.response_timeout_s = 0.03;
    m.connect_timeout_s = 0.1;
    m.min_backoff_s = 0.05;
    m.max_backoff_s = 0.2;
  }
  // TRUEAXIS_TEST_POLL_THREADS=K: every shop of these tests polls with K threads (the suite passes with 1 and 2).
  if (const char* k = std::getenv("TRUEAXIS_TEST_POLL_THREADS")) c.poll_threads = std::atoi(k);
  return c;
}

}  // namespace trueaxis::server::testing
