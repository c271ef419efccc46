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
  if (poller_.Running()) return ok;
  buffer_.assign(inner_->ChannelCount(), hw::RawTemperature{});
  poller_.Start(period_.count(), [this](double) { Poll(); });
  return ok;
}

void PolledTemperatureSource::Deactivate() {
  if (poller_.Running()) {
    poller_.Stop();
    inner_->Deactivate();
  }
}

void PolledTemperatureSource::Poll() {
  const bool ok = inner_->Read(buffer_);  // may block (kernel conversion, network): no lock held
  ++polls_;
  std::lock_guard<std::mutex> lock(mu_);
  latest_ok_ = ok;
  if (ok) {
    latest_ = buffer_;
    latest_time_ = std::chrono::steady_clock::now();
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
