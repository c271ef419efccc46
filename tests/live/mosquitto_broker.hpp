#pragma once
// A real mosquitto broker for a test: its own config file in a temporary
// directory, listening on 127.0.0.1 only at a port that was free, no
// persistence (a restart loses the retained values, as a crashed broker
// without persistence would). Kill() stops it at once (SIGKILL: a broker
// crash), Start() again reuses the same port. The destructor always stops it.
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <netinet/in.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "../support/local_process.hpp"

extern char** environ;

namespace trueaxis::testing {

class MosquittoBroker {
 public:
  MosquittoBroker() {
    dir_ = std::filesystem::temp_directory_path() / ("trueaxis_mqtt_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    port_ = FreeLoopbackPort();
  }
  ~MosquittoBroker() {
    Kill();
    std::filesystem::remove_all(dir_);
  }

  // Starts the broker; true when it accepts connections. error() says why not.
  bool Start() {
    {
      std::ofstream conf(dir_ / "mosquitto.conf");
      conf << "listener " << port_ << " 127.0.0.1\nallow_anonymous true\npersistence false\n"
           << "log_dest none\n";  // run as root, mosquitto drops to its own user: it could not write our directory
    }
    const std::string conf = (dir_ / "mosquitto.conf").string();
    const char* argv[] = {"/usr/sbin/mosquitto", "-c", conf.c_str(), nullptr};
    if (posix_spawn(&pid_, argv[0], nullptr, nullptr, const_cast<char* const*>(argv), environ) != 0) {
      error_ = "cannot start /usr/sbin/mosquitto (scripts/install-deps.sh: mosquitto)";
      pid_ = -1;
      return false;
    }
    for (int i = 0; i < 200; ++i) {  // up to 10 s for the listener
      if (Accepts()) return true;
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        error_ = "mosquitto exited at start (port " + std::to_string(port_) + " taken?)";
        return false;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    error_ = "mosquitto did not listen on port " + std::to_string(port_);
    return false;
  }
  void Kill() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
  int port() const { return port_; }
  std::string Uri() const { return "tcp://127.0.0.1:" + std::to_string(port_); }
  const std::string& error() const { return error_; }

  // mosquitto_sub (an independent client): the retained message(s) of `topic`
  // as "retained qos topic payload" lines; waits up to 5 s for `count` messages.
  std::string Subscribe(const std::string& topic, int count = 1) const {
    const std::string cmd = "timeout 10 mosquitto_sub -h 127.0.0.1 -p " + std::to_string(port_) + " -t '" + topic + "' -q 1 -C " +
                            std::to_string(count) + " -W 5 -F '%r %q %t %p'";
    return CommandOutput(cmd);
  }

 private:
  bool Accepts() const {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(static_cast<std::uint16_t>(port_));
    const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    close(fd);
    return ok;
  }
  std::filesystem::path dir_;
  int port_ = 0;
  pid_t pid_ = -1;
  std::string error_;
};

}  // namespace trueaxis::testing
