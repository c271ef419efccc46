#pragma once
// A real PostgreSQL 15 server for a test: initdb + pg_ctl (Debian's
// /usr/lib/postgresql/15/bin) in a fresh temporary directory, listening on a
// unix socket in that directory only (no TCP port, nothing outside loopback).
// PostgreSQL refuses to run as root, so under root the server runs as the
// unprivileged user `nobody` (runuser); the test process connects over the
// socket with trust authentication as the database superuser "trueaxis".
// Stop() (also from the destructor) shuts it down immediately and removes
// the directory.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "../support/local_process.hpp"

namespace trueaxis::testing {

class PostgresServer {
 public:
  static constexpr const char* kBin = "/usr/lib/postgresql/15/bin";

  // True when the server runs; otherwise error() says why (with the log's tail).
  bool Start() {
    dir_ = std::filesystem::temp_directory_path() / ("trueaxis_pg_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    if (!std::filesystem::exists(std::string(kBin) + "/initdb")) return Fail("PostgreSQL 15 is not installed (scripts/install-deps.sh: postgresql-15)");
    if (::geteuid() == 0) {
      as_user_ = "runuser -u nobody -- ";
      if (std::system(("chown nobody:nogroup " + dir_.string()).c_str()) != 0) return Fail("cannot chown the directory to nobody");
    }
    // Even if this test process dies without its destructors (a crash, kill -9),
    // the server must not outlive it: a detached guard stops it and removes the directory.
    const std::string guard = "while kill -0 " + std::to_string(::getpid()) + " 2>/dev/null; do sleep 0.5; done; " + as_user_ +
                              kBin + "/pg_ctl -D " + Data() + " -m immediate stop; rm -rf " + dir_.string();
    std::system(("setsid sh -c '" + guard + "' >/dev/null 2>&1 </dev/null &").c_str());
    if (!Run(std::string(kBin) + "/initdb -D " + Data() + " -A trust -U trueaxis -E UTF8 --no-sync --no-instructions"))
      return Fail("initdb failed");
    return Resume();
  }
  // Starts the (stopped) server again on the same data directory.
  bool Resume() {
    const std::string opts = "-k " + dir_.string() + " -c listen_addresses='' -p " + std::to_string(kPort) + " -F";
    if (!Run(std::string(kBin) + "/pg_ctl -D " + Data() + " -l " + (dir_ / "server.log").string() + " -w -t 30 -o \"" + opts + "\" start"))
      return Fail("pg_ctl start failed");
    running_ = true;
    return true;
  }
  // Stops the server now (as a crash or a restart would); the data stays.
  void Halt() {
    if (running_) Run(std::string(kBin) + "/pg_ctl -D " + Data() + " -m immediate -w -t 30 stop");
    running_ = false;
  }
  void Stop() {
    Halt();
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
    dir_.clear();
  }
  ~PostgresServer() { Stop(); }

  std::string Url(const std::string& db = "postgres") const {
    return "postgresql://trueaxis@/" + db + "?host=" + dir_.string() + "&port=" + std::to_string(kPort);
  }
  // psql as an independent reader: the output of one query, unaligned, tuples only.
  std::string Psql(const std::string& sql) const {
    return CommandOutput(std::string("timeout 30 ") + kBin + "/psql \"" + Url() + "\" -Atc \"" + sql + "\"");
  }
  const std::string& error() const { return error_; }

 private:
  static constexpr int kPort = 5432;  // only names the socket file inside our own directory
  std::string Data() const { return (dir_ / "data").string(); }
  bool Run(const std::string& cmd) {
    const std::string log = (dir_ / "commands.log").string();
    return std::system(("cd / && " + as_user_ + cmd + " >>" + log + " 2>&1").c_str()) == 0;
  }
  bool Fail(const std::string& what) {
    std::ostringstream tail;
    for (const char* name : {"commands.log", "server.log"}) {
      std::ifstream in(dir_ / name);
      tail << "\n--- " << name << ":\n" << in.rdbuf();
    }
    error_ = what + tail.str();
    return false;
  }
  std::filesystem::path dir_;
  std::string as_user_;
  bool running_ = false;
  std::string error_;
};

}  // namespace trueaxis::testing
