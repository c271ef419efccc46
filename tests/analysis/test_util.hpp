#pragma once
// Helpers shared by the analysis tests: build measurements in memory and run the CLI.
#include <cstdio>
#include <cstdlib>
#include <sys/wait.h>
#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "trueaxis/measure/measurement.hpp"

namespace trueaxis::testing {

// up[i] / down[i] = deviations (µm) of target i, one per run.
inline measure::Measurement MakeMeasurement(const std::vector<double>& targets_mm,
                                            const std::vector<std::vector<double>>& up,
                                            const std::vector<std::vector<double>>& down) {
  measure::Measurement m;
  m.source = "memory";
  int line = 1;
  for (std::size_t i = 0; i < targets_mm.size(); ++i) {
    for (std::size_t j = 0; j < up[i].size(); ++j)
      m.points.push_back({static_cast<int>(j + 1), Direction::kForward, targets_mm[i], up[i][j], {}, {}, ++line});
    for (std::size_t j = 0; j < down[i].size(); ++j)
      m.points.push_back({static_cast<int>(j + 1), Direction::kReverse, targets_mm[i], down[i][j], {}, {}, ++line});
  }
  return m;
}

struct CliResult {
  int exit_code = -1;
  std::string out, err;
};

inline std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs the trueaxis CLI with the given (already shell-quoted) arguments.
inline CliResult RunCli(const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path();
  const auto tag = std::to_string(::getpid()) + "_" + std::to_string(++counter);
  const auto out = dir / ("trueaxis_cli_out_" + tag), err = dir / ("trueaxis_cli_err_" + tag);
  const std::string cmd = std::string("'") + TRUEAXIS_CLI_PATH + "' " + args + " >'" + out.string() + "' 2>'" +
                          err.string() + "'";
  const int status = std::system(cmd.c_str());
  CliResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = Slurp(out);
  r.err = Slurp(err);
  std::filesystem::remove(out);
  std::filesystem::remove(err);
  return r;
}

inline std::string WriteTemp(const std::string& name, const std::string& content) {
  const auto p = std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name);
  std::ofstream(p, std::ios::binary) << content;
  return p.string();
}

}  // namespace trueaxis::testing
