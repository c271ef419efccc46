#include "trueaxis/server/http_guard.hpp"

#include <arpa/inet.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>

#include <fmt/format.h>
#include <httplib.h>


namespace trueaxis::server {
namespace {

std::string Lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// "name:port", "[v6]:port", "name" → the name, lower case.
std::string HostName(const std::string& host_header) {
  std::string host = host_header;
  if (!host.empty() && host.front() == '[') {
    const auto close = host.find(']');
    host = host.substr(1, close == std::string::npos ? std::string::npos : close - 1);
  } else if (std::count(host.begin(), host.end(), ':') == 1) {
    host = host.substr(0, host.find(':'));
  }
  return Lower(host);
}

bool IsIpLiteral(const std::string& host) {
  in_addr v4{};
  in6_addr v6{};
  return inet_pton(AF_INET, host.c_str(), &v4) == 1 || inet_pton(AF_INET6, host.c_str(), &v6) == 1;
}

bool IsThisComputersName(const std::string& host) {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0 || name[0] == '\0') return false;
  const std::string full = Lower(name);
  return host == full || host == full.substr(0, full.find('.'));
}

}  // namespace

bool IsOwnHost(const std::string& host_header, const std::string& bind_address, const std::vector<std::string>& names) {
  if (host_header.empty()) return true;
  const std::string host = HostName(host_header);
  if (host.empty()) return false;
  // An address typed as such cannot be rebound: only a DNS name can point elsewhere later.
  if (host == "localhost" || IsIpLiteral(host) || host == Lower(bind_address) || IsThisComputersName(host)) return true;
  return std::any_of(names.begin(), names.end(), [&](const std::string& n) { return host == Lower(n); });
}

bool IsSameOrigin(const std::string& origin, const std::string& scheme, const std::string& host_header) {
  if (host_header.empty()) return false;
  return Lower(origin) == Lower(scheme + "://" + host_header);
}

bool IsJsonMediaType(const std::string& content_type) {
  std::string type = content_type.substr(0, content_type.find(';'));
  const auto first = type.find_first_not_of(" \t");
  const auto last = type.find_last_not_of(" \t");
  type = first == std::string::npos ? "" : type.substr(first, last - first + 1);
  return Lower(type) == "application/json";
}

std::optional<HttpRefusal> CheckBodyFraming(const httplib::Request& req, std::size_t max_body_bytes) {
  if (req.has_header("Transfer-Encoding"))
    return HttpRefusal{411, fmt::format("request: field 'Transfer-Encoding': not accepted: send the body with "
                                        "Content-Length (at most {} bytes)", max_body_bytes)};
  // cpp-httplib reads the body of these until the client closes when no length is given.
  const bool has_body = req.method == "POST" || req.method == "PUT" || req.method == "PATCH";
  if (!req.has_header("Content-Length")) {
    if (!has_body) return std::nullopt;
    return HttpRefusal{411, fmt::format("request: field 'Content-Length': required (a JSON body of at most {} bytes)",
                                        max_body_bytes)};
  }
  const std::string text = req.get_header_value("Content-Length");
  if (req.get_header_value_count("Content-Length") > 1)
    return HttpRefusal{400, "request: field 'Content-Length': given more than once"};
  if (text.empty() || text.size() > 19 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return HttpRefusal{400, "request: field 'Content-Length': not a number of bytes"};
  if (std::stoull(text) > max_body_bytes)
    return HttpRefusal{413, fmt::format("request body: larger than {} bytes", max_body_bytes)};
  return std::nullopt;
}

}  // namespace trueaxis::server
