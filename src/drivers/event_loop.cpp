#include "trueaxis/drivers/event_loop.hpp"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <unistd.h>

namespace trueaxis::drivers {

EventLoop::EventLoop() {
  epoll_fd_ = epoll_create1(EPOLL_CLOEXEC);
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.u64 = kWakeToken;
  epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, wake_fd_, &ev);
}

EventLoop::~EventLoop() {
  Stop();
  close(wake_fd_);
  close(epoll_fd_);
}

void EventLoop::Start(std::function<void()> loop) {
  if (thread_.joinable()) return;
  stop_.store(false);
  thread_ = std::thread(std::move(loop));
}

bool EventLoop::Stop() {
  if (!thread_.joinable()) return false;
  stop_.store(true);
  const std::uint64_t one = 1;
  [[maybe_unused]] auto w = write(wake_fd_, &one, sizeof one);
  thread_.join();
  std::uint64_t drained = 0;
  [[maybe_unused]] auto r = read(wake_fd_, &drained, sizeof drained);
  return true;
}

}  // namespace trueaxis::drivers
