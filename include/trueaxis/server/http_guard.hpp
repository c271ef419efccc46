#pragma once
// The checks both HTTP servers (the control API and the web front end, both cpp-httplib) make on
// a request's headers, before any body is read (docs/server.md, docs/web.md):
//
//   Host        DNS rebinding: a page whose name the attacker points at this computer reaches the
//               server as "its own origin" but names the attacker's host in Host. Only this
//               computer's names (and addresses) are served.
//   Origin      a browser's POST from another site: scheme, host and port must be this server's.
//   framing     cpp-httplib reads a chunked body (or one without a length) whole, whatever the
//               size limit: Transfer-Encoding is refused, a body must come with Content-Length,
//               and a length over the limit is refused before a byte of it is read.
//   media type  exactly application/json (parameters such as "; charset=utf-8" allowed).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace httplib {
struct Request;
}

namespace trueaxis::server {

// Whether a Host header names this server. Served: no Host (HTTP/1.0), "localhost", any IP address
// (an address cannot be rebound, only a DNS name), this computer's host name, the bind address and
// `names`. Case-insensitive, port ignored.
bool IsOwnHost(const std::string& host_header, const std::string& bind_address, const std::vector<std::string>& names = {});

// Whether a browser's Origin ("http://host:port") is exactly this server: `scheme` ("http" or
// "https") and the Host the request was sent to (already checked with IsOwnHost).
bool IsSameOrigin(const std::string& origin, const std::string& scheme, const std::string& host_header);

// "application/json", any case, optionally followed by parameters after ';'.
bool IsJsonMediaType(const std::string& content_type);

struct HttpRefusal {
  int status;           // 411, 413 or 400
  std::string message;  // "request: field 'Content-Length': ..."
};

// Refuses what would make cpp-httplib read a body beyond `max_body_bytes`: any Transfer-Encoding,
// a POST, PUT or PATCH without Content-Length (read until the client closes), a Content-Length that
// is not a number or is over the limit. Nothing: the body may be read.
std::optional<HttpRefusal> CheckBodyFraming(const httplib::Request& req, std::size_t max_body_bytes);

}  // namespace trueaxis::server
