#pragma once
// Runs the built `trueaxis` CLI (TRUEAXIS_CLI_PATH) and captures its exit
// code and combined output.
#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace trueaxis::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;
};

// Runs `command` with /bin/sh and captures its exit code and standard output (add 2>&1 for both).
inline CliResult RunShell(const std::string& command) {
  CliResult r;
  FILE* p = popen(command.c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.output.append(buf.data(), n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CliResult RunCli(const std::string& args) {
  return RunShell(std::string(TRUEAXIS_CLI_PATH) + " " + args + " 2>&1");
}

}  // namespace trueaxis::testing
