#pragma once
// The MTConnect 1.3 response documents, built with pugixml (which escapes every name and text):
// MTConnectDevices (/probe), MTConnectStreams (/current, /sample) and MTConnectError. Root element,
// namespaces, Header attributes and the Streams / DeviceStream / ComponentStream / Samples / Events /
// Condition nesting follow MTConnectDevices_1.3.xsd, MTConnectStreams_1.3.xsd and
// MTConnectError_1.3.xsd (docs/server.md, "MTConnect agent").
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/server/mtconnect_buffer.hpp"
#include "trueaxis/server/mtconnect_devices.hpp"

namespace pugi {
class xml_document;
}

namespace trueaxis::server::mtconnect {

struct HeaderInfo {
  std::string sender;
  std::uint64_t instance_id = 1;
  std::size_t buffer_size = 0;
  double now_unix_s = 0;
};

// The Devices part (`device` -1: every device) into `doc` (the agent keeps one to evaluate `path`).
void BuildDevices(const DeviceModel& model, const HeaderInfo& header, int device, pugi::xml_document& doc);
std::string DevicesDocument(const DeviceModel& model, const HeaderInfo& header, int device);
// `observations` in any order; `device` -1: a DeviceStream for every device, else for that one.
std::string StreamsDocument(const DeviceModel& model, const HeaderInfo& header, const BufferRange& range, std::uint64_t next_sequence,
                            std::vector<Observation> observations, int device);
// error_code: NO_DEVICE, OUT_OF_RANGE, QUERY_ERROR, INVALID_REQUEST, INVALID_URI, INVALID_XPATH, UNSUPPORTED, UNAUTHORIZED ...
std::string ErrorDocument(const HeaderInfo& header, const std::string& error_code, const std::string& message);

}  // namespace trueaxis::server::mtconnect
