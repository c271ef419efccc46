#pragma once
// GatedHttpServer: a cpp-httplib server (plain HTTP) whose workers never wait for a slow client.
//
// cpp-httplib gives each accepted connection a worker thread that reads the request with a timeout
// per receive: clients that trickle their headers a byte at a time hold every worker and a fresh
// request waits (40 such connections delayed a GET by 5 s). Here a connection reaches a worker only
// once its whole request — headers, and a body of the length it declares — has arrived; until then
// one thread watches all waiting connections (epoll, edge-triggered, MSG_PEEK: nothing is
// consumed), and a connection whose request is not complete within `request_timeout_s` of its
// arrival is answered 408 and closed. A request too large to wait for (headers over 16 KiB, a
// body over `max_body_bytes`, chunked) goes to a worker at once, where the size checks refuse it.
// One request per connection. TLS servers (httplib::SSLServer) are not gated.
#include <httplib.h>

#include <atomic>
#include <map>
#include <mutex>
#include <string>
#include <thread>

namespace trueaxis::server {

class GatedHttpServer : public httplib::Server {
 public:
  GatedHttpServer(std::size_t worker_threads, double request_timeout_s, std::size_t max_body_bytes);
  ~GatedHttpServer() override;
  GatedHttpServer(const GatedHttpServer&) = delete;
  GatedHttpServer& operator=(const GatedHttpServer&) = delete;

 private:
  class Queue;
  enum class Arrival { kComplete, kIncomplete, kGone };
  enum class Outcome { kServe, kTimeout, kDrop };
  bool process_and_close_socket(socket_t sock) override;  // on a worker, for each accepted connection
  Arrival Peek(int sock) const;
  void Serve(int sock);  // the request has arrived: answer it, close
  void Wait(int sock);   // hand to the gate thread
  void GateLoop();
  void Release(int sock, Outcome outcome);  // the gate's mutex is held

  std::size_t workers_;
  double request_timeout_s_;
  std::size_t max_body_bytes_;
  int epoll_fd_ = -1, wake_fd_ = -1;
  mutable std::mutex mutex_;
  std::map<int, double> deadlines_;  // waiting sockets → steady-clock deadline (s)
  Queue* queue_ = nullptr;           // the workers, while the server listens
  std::atomic<bool> stopping_{false};
  std::thread gate_;
};

}  // namespace trueaxis::server
