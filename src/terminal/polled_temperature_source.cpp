#include "trueaxis/terminal/polled_temperature_source.hpp"

#include <algorithm>

#include <fmt/format.h>

namespace trueaxis::terminal {

PolledTemperatureSource::PolledTemperatureSource(std::unique_ptr<hw::TemperatureSource> inner, double period_s,
                                                 double stale_after_s)
    : inner_(std::move(inner)), period_(period_s), stale_after_(stale_after_s) {}

PolledTemperatureSource::~PolledTemperatureSource() { Deactivate(); }

bool PolledTemperatureSource::Configure(std::string* error) {
  if (!(period_.count() > 0) || !(stale_after_.count() > period_.count())) {
    if (error) *error = fmt::format("poll period {} s / stale after {} s: need 0 < period < stale_after", period_.count(),
                                    stale_after_.count());
    return false;
  }
  if (!inner_->Configure(error)) return false;
  latest_.assign(inner_->ChannelCount(), hw::RawTemperature{});
  return true;
}

bool PolledTemperatureSource::Activate(std::string* error) {
  const bool ok = inner_->Activate(error);
  if (thread_.joinable()) return ok;
  {
    std::lock_guard<std::mutex> lock(mu_);
    stop_ = false;
  }
  thread_ = std::thread([this] { Run(); });
  return ok;
}

void PolledTemperatureSource::Deactivate() {
  if (thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mu_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
    inner_->Deactivate();
  }
}

void PolledTemperatureSource::Run() {
  std::vector<hw::RawTemperature> buffer(inner_->ChannelCount());
  auto next = std::chrono::steady_clock::now();
  for (;;) {
    const bool ok = inner_->Read(buffer);  // may block (kernel conversion, network): no lock held
    ++polls_;
    {
      std::unique_lock<std::mutex> lock(mu_);
      latest_ok_ = ok;
      if (ok) {
        latest_ = buffer;
        latest_time_ = std::chrono::steady_clock::now();
      }
      next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period_);
      const auto now = std::chrono::steady_clock::now();
      if (next < now) next = now;  // a read longer than the period: no burst to catch up
      if (wake_.wait_until(lock, next, [&] { return stop_; })) return;
    }
  }
}

bool PolledTemperatureSource::Read(std::span<hw::RawTemperature> out) {
  std::lock_guard<std::mutex> lock(mu_);
  if (!latest_ok_) return false;
  if (std::chrono::steady_clock::now() - latest_time_ > stale_after_) return false;
  std::copy_n(latest_.begin(), std::min(out.size(), latest_.size()), out.begin());
  return true;
}

}  // namespace trueaxis::terminal
