#pragma once
// EventLoop: the epoll set, the eventfd that wakes it and the one thread that
// runs it — shared by the server's terminal client (Shop) and the virtual
// shop. The wake-up's epoll data is kWakeToken; Stop() wakes the loop, which
// sees stopping() and returns, and joins it.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>

namespace trueaxis::drivers {

class EventLoop {
 public:
  static constexpr std::uint64_t kWakeToken = ~0ull;
  EventLoop();   // creates the epoll set and the eventfd
  ~EventLoop();  // Stop(), closes both
  EventLoop(const EventLoop&) = delete;
  EventLoop& operator=(const EventLoop&) = delete;

  int epoll_fd() const { return epoll_fd_; }
  bool stopping() const { return stop_.load(std::memory_order_relaxed); }
  void Start(std::function<void()> loop);
  // Wakes the loop, waits for it to return. False when it was not running.
  bool Stop();
  std::thread& thread() { return thread_; }

 private:
  int epoll_fd_ = -1;
  int wake_fd_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace trueaxis::drivers
