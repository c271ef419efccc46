#pragma once
// Reading what a terminal serves with mbpoll (an independent MODBUS client)
// and turning ADAM-6015 raw counts back into °C.
#include <map>
#include <regex>
#include <string>

#include "support/local_process.hpp"
#include "trueaxis/drivers/adam6015_map.hpp"
#include "trueaxis/drivers/register_codec.hpp"

namespace trueaxis::terminal::testing {

// mbpoll's "[ref]: value" lines of one run (bounded by `timeout`), by reference; the output is appended to *text.
inline std::map<int, long long> MbpollValues(const std::string& port, const std::string& args, std::string* text) {
  *text += trueaxis::testing::CommandOutput("timeout 20 mbpoll -m tcp -1 -o 2 -p " + port + " " + args + " 127.0.0.1");
  std::map<int, long long> values;
  const std::regex line(R"(\[(\d+)\]:\s+(-?\d+))");
  for (std::sregex_iterator it(text->begin(), text->end(), line), end; it != end; ++it)
    values[std::stoi((*it)[1])] = std::stoll((*it)[2]);
  return values;
}

// A raw AI value of the default range (−50…150 °C) in °C.
inline double RawToC(long long raw) {
  return drivers::AdamRawToCelsius(static_cast<std::uint16_t>(raw), *drivers::FindRtdRange(drivers::adam6015::kDefaultRangeCode));
}

}  // namespace trueaxis::terminal::testing
