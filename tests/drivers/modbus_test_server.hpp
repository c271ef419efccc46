#pragma once
// The drivers tests' fixtures: the shared mock hardware (tests/support/mock_hardware.hpp, used
// through its locked setters: the server's machine thread reads it while the test sets it), and a
// helper that starts a ModbusMachineServer on a free loopback port.
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "../support/mock_hardware.hpp"
#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::drivers::testing {

using trueaxis::testing::MockCnc;
using trueaxis::testing::MockTemperatures;

// libmodbus cannot bind port 0, so ports are drawn at random from [20000, 60000) until one binds.
// Builds and starts a server on a free port; returns nullptr (and *error) when none binds.
inline std::unique_ptr<ModbusMachineServer> StartServer(hw::CncLink* cnc, hw::TemperatureSource* temps,
                                                        ModbusMachineServerOptions opt, std::string* error) {
  std::mt19937 rng(std::random_device{}());
  std::uniform_int_distribution<int> pick(20000, 59999);
  for (int attempt = 0; attempt < 50; ++attempt) {
    opt.port = pick(rng);
    auto server = std::make_unique<ModbusMachineServer>(cnc, temps, opt);
    if (server->Start(error)) return server;
  }
  return nullptr;
}

// Polls `pred` until true or `timeout_s` passes.
template <class Pred>
bool WaitFor(Pred pred, double timeout_s = 3.0) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    if (pred()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return pred();
}

}  // namespace trueaxis::drivers::testing
