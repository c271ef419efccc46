#pragma once
// "2026-11-24T10:25:00Z": when a model file was made (stamped by the CLI; the libraries read no clock).
#include <chrono>
#include <ctime>
#include <string>

namespace trueaxis::cli {

inline std::string UtcNow() {
  const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

}  // namespace trueaxis::cli
