#pragma once
// MtconnectAgent: the workshop server's machines as an MTConnect 1.3 agent (docs/server.md,
// "MTConnect agent"), so shop dashboards that speak MTConnect read trueaxis without code:
//
//   GET /probe                    MTConnectDevices: every machine a Device (mtconnect_devices.hpp)
//   GET /current[?at=N]           MTConnectStreams: every data item's latest value (or at sequence N)
//   GET /sample[?from=N&count=C]  MTConnectStreams: the observations from sequence N on (count 100)
//   GET /<device>/probe|current|sample   the same for one machine (its name or uuid)
//   path=XPATH                    on current and sample: only the data items the XPath selects in /probe
// Errors are MTConnectError documents: NO_DEVICE (404), OUT_OF_RANGE, QUERY_ERROR, INVALID_XPATH,
// INVALID_REQUEST, UNSUPPORTED (400; `interval` streaming is not served: poll /sample), INVALID_URI
// (404), UNAUTHORIZED (403: a Host that is not this computer's, as the control API).
//
// A publisher thread (core::PeriodicThread, every period_s) takes one Shop::Snapshot() and appends a
// new observation for each value that changed since the last one (as the document shows it) to the
// bounded ObservationBuffer; the shop's event loop is never touched. Its own port, cpp-httplib
// behind GatedHttpServer and the control API's Host and body-framing checks (http_guard.hpp).
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {

struct MtconnectOptions {
  std::string bind = "127.0.0.1";
  int port = 5000;                    // 0: any free port (see port())
  double period_s = 1.0;              // how often the publisher looks at the shop
  std::size_t buffer_size = 131072;   // observations held (bufferSize)
  std::string sender;                 // Header sender ("": this computer's host name)
  std::vector<std::string> host_names;  // further names clients use for this computer (Host check)
};

// InputError naming the option (--mtconnect, --mtconnect-period-s, --mtconnect-buffer) that is out of range.
void CheckMtconnectOptions(const MtconnectOptions& options);

struct MtconnectResponse {
  int status = 200;
  std::string body;  // an MTConnectDevices, MTConnectStreams or MTConnectError document
};

class MtconnectAgent {
 public:
  // Every machine of `shop` (it must outlive the agent) with each value UNAVAILABLE until the
  // first publish. Throws InputError for options out of range.
  MtconnectAgent(const Shop& shop, MtconnectOptions options);
  ~MtconnectAgent();  // Stop()
  MtconnectAgent(const MtconnectAgent&) = delete;
  MtconnectAgent& operator=(const MtconnectAgent&) = delete;

  void PublishOnce();  // one snapshot into the buffer (the publisher's step; tests call it directly)
  // Answers one GET (path and query parameters) as the HTTP server does.
  MtconnectResponse Respond(const std::string& path, const std::multimap<std::string, std::string>& params) const;

  bool Start(std::string* error);  // listens, starts publishing; false with *error when the port cannot be bound
  void Stop();
  int port() const { return port_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int port_;
};

}  // namespace trueaxis::server
