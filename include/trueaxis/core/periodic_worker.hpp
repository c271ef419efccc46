#pragma once
// PeriodicWorker: one thread that calls a function at once and then every period until Stop()
// (or destruction). Stop() wakes it at once — it never waits out a period — and joins it. For
// the low-rate publishers around the real-time parts (the web front end's shop sampler, the MQTT
// relay); not for the compensator's cycle, which has its own loop and timing contract.
#include <chrono>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>

namespace trueaxis::core {

class PeriodicWorker {
 public:
  PeriodicWorker() = default;
  ~PeriodicWorker() { Stop(); }
  PeriodicWorker(const PeriodicWorker&) = delete;
  PeriodicWorker& operator=(const PeriodicWorker&) = delete;

  // Starts the thread (a running worker is stopped first). `period_s` > 0.
  void Start(double period_s, std::function<void()> tick) {
    Stop();
    {
      std::lock_guard lock(mutex_);
      stop_ = false;
    }
    thread_ = std::thread([this, period_s, tick = std::move(tick)] {
      std::unique_lock lock(mutex_);
      do {
        lock.unlock();
        tick();
        lock.lock();
      } while (!cv_.wait_for(lock, std::chrono::duration<double>(period_s), [this] { return stop_; }));
    });
  }

  void Stop() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  bool running() const { return thread_.joinable(); }

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace trueaxis::core
