#include "trueaxis/terminal/w1_slave.hpp"

#include <cctype>
#include <charconv>
#include <vector>

namespace trueaxis::terminal {
namespace {

W1SlaveReading Malformed(std::string why) {
  W1SlaveReading r;
  r.status = W1SlaveStatus::kMalformed;
  r.why = std::move(why);
  return r;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// The 9 hex bytes at the start of a line; false when they are not there.
bool ScratchpadBytes(std::string_view line, std::vector<int>& bytes) {
  bytes.clear();
  std::size_t pos = 0;
  for (int i = 0; i < 9; ++i) {
    while (pos < line.size() && line[pos] == ' ') ++pos;
    if (pos + 2 > line.size()) return false;
    int value = 0;
    const auto [p, ec] = std::from_chars(line.data() + pos, line.data() + pos + 2, value, 16);
    if (ec != std::errc() || p != line.data() + pos + 2) return false;
    bytes.push_back(value);
    pos += 2;
  }
  return true;
}

}  // namespace

const char* W1SlaveStatusName(W1SlaveStatus status) {
  switch (status) {
    case W1SlaveStatus::kOk: return "ok";
    case W1SlaveStatus::kCrcError: return "crc_error";
    case W1SlaveStatus::kNoResponse: return "no_response";
    case W1SlaveStatus::kMalformed: return "malformed";
  }
  return "?";
}

W1SlaveReading ParseW1Slave(std::string_view text) {
  const std::size_t nl = text.find('\n');
  if (nl == std::string_view::npos) return Malformed(text.empty() ? "empty file" : "one line, expected two");
  const std::string_view line1 = Trim(text.substr(0, nl));
  const std::string_view line2 = Trim(text.substr(nl + 1));
  std::vector<int> bytes;
  if (!ScratchpadBytes(line1, bytes)) return Malformed("line 1 does not start with 9 hex bytes");
  const std::size_t crc = line1.find("crc=");
  if (crc == std::string_view::npos) return Malformed("line 1 has no 'crc='");
  const std::string_view verdict = Trim(line1.substr(line1.find_last_of(' ') + 1));
  if (verdict != "YES" && verdict != "NO") return Malformed("line 1 does not end in YES or NO");
  if (verdict == "NO") {
    W1SlaveReading r;
    r.status = W1SlaveStatus::kCrcError;
    return r;
  }
  bool all_zero = true;
  for (int b : bytes) all_zero = all_zero && b == 0;
  if (all_zero) {
    W1SlaveReading r;
    r.status = W1SlaveStatus::kNoResponse;
    return r;
  }
  const std::size_t t = line2.rfind("t=");
  if (t == std::string_view::npos) return Malformed("line 2 has no 't='");
  const std::string_view number = line2.substr(t + 2);
  long milli = 0;
  const auto [p, ec] = std::from_chars(number.data(), number.data() + number.size(), milli);
  if (ec != std::errc() || p != number.data() + number.size() || number.empty())
    return Malformed("line 2: 't=' is not followed by an integer");
  W1SlaveReading r;
  r.status = W1SlaveStatus::kOk;
  r.milli_c = milli;
  return r;
}

}  // namespace trueaxis::terminal
