#include "trueaxis/server/gated_http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace trueaxis::server {
namespace {

constexpr std::size_t kMaxHeaderBytes = 16 * 1024;

double NowS() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

int Millis(time_t sec, time_t usec) { return static_cast<int>(sec * 1000 + usec / 1000); }

bool WaitFor(int sock, short events, int timeout_ms) {
  pollfd p{sock, events, 0};
  int r;
  while ((r = ::poll(&p, 1, timeout_ms)) < 0 && errno == EINTR) {
  }
  return r > 0;
}

void AddressOf(int sock, bool peer, std::string& ip, int& port) {
  sockaddr_storage a{};
  socklen_t len = sizeof a;
  if ((peer ? ::getpeername(sock, reinterpret_cast<sockaddr*>(&a), &len) : ::getsockname(sock, reinterpret_cast<sockaddr*>(&a), &len)) != 0)
    return;
  char text[INET6_ADDRSTRLEN] = {};
  if (a.ss_family == AF_INET) {
    const auto* v4 = reinterpret_cast<const sockaddr_in*>(&a);
    ::inet_ntop(AF_INET, &v4->sin_addr, text, sizeof text);
    port = ntohs(v4->sin_port);
  } else if (a.ss_family == AF_INET6) {
    const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&a);
    ::inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof text);
    port = ntohs(v6->sin6_port);
  }
  ip = text;
}

// The connection to one client as cpp-httplib reads and writes it (its own SocketStream is not
// public): buffered reads, each receive and send bounded by the server's timeouts.
class PlainStream : public httplib::Stream {
 public:
  PlainStream(int sock, int read_ms, int write_ms) : sock_(sock), read_ms_(read_ms), write_ms_(write_ms) {}
  using httplib::Stream::write;
  bool is_readable() const override { return pos_ < len_ || WaitFor(sock_, POLLIN, read_ms_); }
  bool is_writable() const override { return WaitFor(sock_, POLLOUT, write_ms_); }
  ssize_t read(char* ptr, size_t size) override {
    if (pos_ == len_) {
      if (!WaitFor(sock_, POLLIN, read_ms_)) return -1;
      ssize_t n;
      while ((n = ::recv(sock_, buffer_, sizeof buffer_, 0)) < 0 && errno == EINTR) {
      }
      if (n <= 0) return n;
      pos_ = 0;
      len_ = static_cast<std::size_t>(n);
    }
    const std::size_t n = std::min(size, len_ - pos_);
    std::memcpy(ptr, buffer_ + pos_, n);
    pos_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (!is_writable()) return -1;
    ssize_t n;
    while ((n = ::send(sock_, ptr, size, MSG_NOSIGNAL)) < 0 && errno == EINTR) {
    }
    return n;
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override { AddressOf(sock_, true, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { AddressOf(sock_, false, ip, port); }
  socket_t socket() const override { return sock_; }

 private:
  int sock_, read_ms_, write_ms_;
  char buffer_[4096];
  std::size_t pos_ = 0, len_ = 0;
};

}  // namespace

// The workers: cpp-httplib's thread pool, and the gate's way to hand it a connection while the
// server listens (stopping the server stops the hand-over first).
class GatedHttpServer::Queue : public httplib::TaskQueue {
 public:
  Queue(GatedHttpServer& owner, std::size_t n) : owner_(owner), pool_(n) {}
  void enqueue(std::function<void()> fn) override { pool_.enqueue(std::move(fn)); }
  void shutdown() override {
    {
      std::lock_guard lock(owner_.mutex_);
      owner_.queue_ = nullptr;
    }
    pool_.shutdown();
  }

 private:
  GatedHttpServer& owner_;
  httplib::ThreadPool pool_;
};

GatedHttpServer::GatedHttpServer(std::size_t worker_threads, double request_timeout_s, std::size_t max_body_bytes)
    : workers_(std::max<std::size_t>(2, worker_threads)), request_timeout_s_(request_timeout_s), max_body_bytes_(max_body_bytes) {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  wake_fd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  epoll_event ev{};
  ev.events = EPOLLIN;
  ev.data.fd = wake_fd_;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, wake_fd_, &ev);
  new_task_queue = [this] {
    auto* q = new Queue(*this, workers_);
    std::lock_guard lock(mutex_);
    queue_ = q;
    return q;
  };
  gate_ = std::thread([this] { GateLoop(); });
}

GatedHttpServer::~GatedHttpServer() {
  stopping_ = true;
  const std::uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);
  gate_.join();
  for (const auto& [sock, deadline] : deadlines_) ::close(sock);
  ::close(epoll_fd_);
  ::close(wake_fd_);
}

GatedHttpServer::Arrival GatedHttpServer::Peek(int sock) const {
  const std::size_t cap = kMaxHeaderBytes + max_body_bytes_;
  std::string buf(cap, '\0');
  ssize_t n;
  while ((n = ::recv(sock, buf.data(), cap, MSG_PEEK | MSG_DONTWAIT)) < 0 && errno == EINTR) {
  }
  if (n == 0) return Arrival::kGone;
  if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK ? Arrival::kIncomplete : Arrival::kGone;
  const std::string_view got(buf.data(), static_cast<std::size_t>(n));
  const auto end = got.find("\r\n\r\n");
  if (end == std::string_view::npos) return got.size() >= kMaxHeaderBytes ? Arrival::kComplete : Arrival::kIncomplete;
  std::string head(got.substr(0, end));
  for (auto& c : head) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (head.find("\ntransfer-encoding:") != std::string::npos) return Arrival::kComplete;  // refused at once
  const auto field = head.find("\ncontent-length:");
  if (field == std::string::npos) return Arrival::kComplete;
  std::size_t i = field + 16, length = 0;
  while (i < head.size() && (head[i] == ' ' || head[i] == '\t')) ++i;
  for (; i < head.size() && std::isdigit(static_cast<unsigned char>(head[i])); ++i) {
    length = length * 10 + static_cast<std::size_t>(head[i] - '0');
    if (length > max_body_bytes_) return Arrival::kComplete;  // refused at once (413)
  }
  return got.size() >= end + 4 + length ? Arrival::kComplete : Arrival::kIncomplete;
}

bool GatedHttpServer::process_and_close_socket(socket_t sock) {
  if (Peek(sock) == Arrival::kIncomplete) {
    Wait(sock);
    return true;
  }
  Serve(sock);
  return true;
}

void GatedHttpServer::Serve(int sock) {
  PlainStream stream(sock, Millis(read_timeout_sec_, read_timeout_usec_), Millis(write_timeout_sec_, write_timeout_usec_));
  bool closed = false;
  process_request(stream, /*close_connection=*/true, closed, nullptr);
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
}

void GatedHttpServer::Wait(int sock) {
  std::lock_guard lock(mutex_);
  if (stopping_) {
    ::close(sock);
    return;
  }
  deadlines_[sock] = NowS() + request_timeout_s_;
  epoll_event ev{};
  ev.events = EPOLLIN | EPOLLRDHUP | EPOLLET;
  ev.data.fd = sock;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, sock, &ev);  // reports data that came already
  const std::uint64_t one = 1;
  (void)!::write(wake_fd_, &one, sizeof one);  // a new deadline
}

void GatedHttpServer::Release(int sock, Outcome outcome) {
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, sock, nullptr);
  deadlines_.erase(sock);
  if (outcome == Outcome::kServe && queue_) {
    queue_->enqueue([this, sock] { Serve(sock); });
    return;
  }
  if (outcome == Outcome::kTimeout) {  // too slow: say so, best effort
    static const std::string body = R"({"error": "the request did not arrive in time"})";
    static const std::string answer = "HTTP/1.1 408 Request Timeout\r\nConnection: close\r\nContent-Type: application/json\r\n"
                                      "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
    (void)!::send(sock, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  }
  ::close(sock);
}

void GatedHttpServer::GateLoop() {
  std::vector<epoll_event> events(256);
  while (!stopping_) {
    int timeout_ms = 1000;
    {
      std::lock_guard lock(mutex_);
      const double now = NowS();
      for (const auto& [sock, deadline] : deadlines_)
        timeout_ms = std::min(timeout_ms, std::max(0, static_cast<int>((deadline - now) * 1000) + 1));
    }
    const int n = ::epoll_wait(epoll_fd_, events.data(), static_cast<int>(events.size()), timeout_ms);
    std::lock_guard lock(mutex_);
    for (int k = 0; k < n; ++k) {
      const int sock = events[k].data.fd;
      if (sock == wake_fd_) {
        std::uint64_t count;
        (void)!::read(wake_fd_, &count, sizeof count);
        continue;
      }
      if (!deadlines_.count(sock)) continue;
      const Arrival a = Peek(sock);
      // A client that stopped sending (half-closed) with its request incomplete: a worker answers
      // what arrived (it reads the end of the stream at once).
      if (a == Arrival::kComplete || (a == Arrival::kIncomplete && (events[k].events & (EPOLLRDHUP | EPOLLHUP))))
        Release(sock, Outcome::kServe);
      else if (a == Arrival::kGone)
        Release(sock, Outcome::kDrop);
    }
    const double now = NowS();
    std::vector<int> late;
    for (const auto& [sock, deadline] : deadlines_)
      if (now >= deadline) late.push_back(sock);
    for (int sock : late) Release(sock, Outcome::kTimeout);
  }
}

}  // namespace trueaxis::server
