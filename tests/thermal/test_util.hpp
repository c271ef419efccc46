#pragma once
// Shared helpers for the thermal tests: synthetic series and a CLI runner.
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <sys/wait.h>

#include "trueaxis/thermal/thermal_series.hpp"

namespace trueaxis::thermal::testing {

// A series with `sensors` temperatures and one error channel, sampled every
// dt_s; temperatures filled by the caller.
inline ThermalSeries MakeSeries(int rows, int sensors, double dt_s = 15.0) {
  ThermalSeries s;
  s.source = "synthetic";
  s.has_time = true;
  for (int r = 0; r < rows; ++r) {
    s.time_s.push_back(r * dt_s);
    s.source_line.push_back(r + 2);
  }
  for (int i = 0; i < sensors; ++i) s.temperature_names.push_back("s" + std::to_string(i));
  s.temperatures_c = Eigen::MatrixXd::Zero(rows, sensors);
  s.error_names = {"e"};
  s.errors_um = Eigen::MatrixXd::Zero(rows, 1);
  return s;
}

// 8 h of 15 s samples in four 2 h spindle blocks (0/2000/0/3000 rpm): sensor
// s0 heats with the spindle, s1 follows a slow ambient swing, s2 is noise;
// the one error channel is 2.5 µm/°C on s0's rise, plus noise.
inline ThermalSeries MakeSpindleBlockSeries(unsigned seed) {
  const int rows = 8 * 240;
  ThermalSeries s = MakeSeries(rows, 3);
  s.has_spindle = true;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.02);
  double t0 = 22;
  for (int r = 0; r < rows; ++r) {
    const double h = s.time_s[static_cast<std::size_t>(r)] / 3600;
    const double rpm = h < 2 ? 0 : h < 4 ? 2000 : h < 6 ? 0 : 3000;
    s.spindle_rpm.push_back(rpm);
    t0 += (22 + rpm / 500.0 - t0) * 15.0 / 2400.0;
    s.temperatures_c(r, 0) = t0 + noise(rng);
    s.temperatures_c(r, 1) = 21 + 0.3 * std::sin(h) + noise(rng);
    s.temperatures_c(r, 2) = 23 + noise(rng);
    s.errors_um(r, 0) = 2.5 * (t0 - 22) + noise(rng);
  }
  return s;
}

// Smooth random walk around `base` (a plausible temperature trace).
inline Eigen::VectorXd RandomWalk(std::mt19937_64& rng, int rows, double base, double step) {
  std::normal_distribution<double> n(0.0, step);
  Eigen::VectorXd v(rows);
  double x = base, drift = 0;
  for (int r = 0; r < rows; ++r) {
    drift = 0.98 * drift + n(rng);
    x += drift;
    v(r) = x;
  }
  return v;
}

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout + stderr
};

inline CliResult RunCli(const std::string& args) {
  CliResult res;
  const std::string cmd = std::string(TRUEAXIS_CLI_PATH) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return res;
  std::array<char, 4096> buf;
  std::size_t n;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) res.output.append(buf.data(), n);
  const int status = pclose(p);
  res.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return res;
}

inline std::string TempDir(const std::string& name) {
  auto dir = std::filesystem::temp_directory_path() / ("trueaxis_thermal_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace trueaxis::thermal::testing
