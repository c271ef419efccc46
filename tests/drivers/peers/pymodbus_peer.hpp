#pragma once
// Runs the independent pymodbus peer (pymodbus_peer.py beside this file, /usr/bin/python3 with
// Debian's python3-pymodbus) and returns the JSON object it prints; {"error": …} with its whole
// output when it fails or prints no JSON.
#include <nlohmann/json.hpp>

#include <string>

#include "support/cli_runner.hpp"

namespace trueaxis::testing {

inline nlohmann::json RunPymodbusPeer(const std::string& args) {
  const CliResult r = RunShell("timeout 30 /usr/bin/python3 " + std::string(TRUEAXIS_SOURCE_DIR) +
                               "/tests/drivers/peers/pymodbus_peer.py " + args + " 2>&1");
  const auto brace = r.output.find('{');
  if (r.exit_code != 0 || brace == std::string::npos) return {{"error", r.output}};
  try {
    return nlohmann::json::parse(r.output.substr(brace));
  } catch (const nlohmann::json::exception&) {
    return {{"error", r.output}};
  }
}

}  // namespace trueaxis::testing
