#pragma once
// In-test stand-ins for a CNC and a temperature source, plus a helper that
// starts a ModbusMachineServer on a free loopback port. The fakes are touched
// by the server's machine thread and by the test thread, hence the mutex.
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "trueaxis/drivers/modbus_machine_server.hpp"
#include "trueaxis/hw/cnc_link.hpp"
#include "trueaxis/hw/temperature_source.hpp"

namespace trueaxis::drivers::testing {

class FakeCnc : public hw::CncLink {
 public:
  explicit FakeCnc(std::vector<std::string> names) : names_(std::move(names)), axes_(names_.size()), comp_(names_.size(), 0.0) {}
  std::size_t AxisCount() const override { return names_.size(); }
  std::string AxisName(std::size_t a) const override { return names_.at(a); }
  bool Read(std::span<hw::AxisState> axes, hw::CncState& machine) override {
    std::unique_lock<std::mutex> lock(mu_);
    cv_.wait_for(lock, std::chrono::seconds(10), [&] { return !hang_; });
    if (!read_ok_) return false;
    for (std::size_t a = 0; a < axes_.size(); ++a) axes[a] = axes_[a];
    machine = state_;
    ++reads_;
    return true;
  }
  bool WriteCompensation(std::span<const double> c) override {
    std::lock_guard<std::mutex> lock(mu_);
    ++attempts_;
    if (!write_ok_) return false;
    comp_.assign(c.begin(), c.end());
    history_.push_back(comp_);
    ++writes_;
    return true;
  }
  void SetAxis(std::size_t a, hw::AxisState s) { std::lock_guard<std::mutex> l(mu_); axes_[a] = s; }
  void SetState(hw::CncState s) { std::lock_guard<std::mutex> l(mu_); state_ = s; }
  void SetReadOk(bool ok) { std::lock_guard<std::mutex> l(mu_); read_ok_ = ok; }
  void SetWriteOk(bool ok) { std::lock_guard<std::mutex> l(mu_); write_ok_ = ok; }
  void SetHang(bool hang) {
    { std::lock_guard<std::mutex> l(mu_); hang_ = hang; }
    cv_.notify_all();
  }
  std::vector<double> Compensation() const { std::lock_guard<std::mutex> l(mu_); return comp_; }
  int Writes() const { std::lock_guard<std::mutex> l(mu_); return writes_; }
  int WriteAttempts() const { std::lock_guard<std::mutex> l(mu_); return attempts_; }
  std::vector<std::vector<double>> History() const { std::lock_guard<std::mutex> l(mu_); return history_; }
  int Reads() const { std::lock_guard<std::mutex> l(mu_); return reads_; }

 private:
  mutable std::mutex mu_;
  std::condition_variable cv_;
  std::vector<std::string> names_;
  std::vector<hw::AxisState> axes_;
  hw::CncState state_;
  std::vector<double> comp_;
  bool read_ok_ = true, write_ok_ = true, hang_ = false;
  int writes_ = 0, reads_ = 0, attempts_ = 0;
  std::vector<std::vector<double>> history_;
};

class FakeTemperatures : public hw::TemperatureSource {
 public:
  explicit FakeTemperatures(std::size_t n) : values_(n) {
    for (std::size_t i = 0; i < n; ++i) values_[i].temp_c = 20.0 + 0.5 * static_cast<double>(i);
  }
  std::size_t ChannelCount() const override { return values_.size(); }
  std::string ChannelName(std::size_t c) const override { return "t" + std::to_string(c); }
  bool Read(std::span<hw::RawTemperature> out) override {
    std::lock_guard<std::mutex> l(mu_);
    if (!ok_) return false;
    for (std::size_t i = 0; i < values_.size(); ++i) out[i] = values_[i];
    return true;
  }
  void Set(std::size_t c, double t, bool fault = false) { std::lock_guard<std::mutex> l(mu_); values_[c] = {t, fault}; }
  void SetOk(bool ok) { std::lock_guard<std::mutex> l(mu_); ok_ = ok; }

 private:
  std::mutex mu_;
  std::vector<hw::RawTemperature> values_;
  bool ok_ = true;
};

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
