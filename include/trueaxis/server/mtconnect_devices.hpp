#pragma once
// The MTConnect (version 1.3) information model of the workshop server's machines: every machine of
// the shop is one Device, its axes are Linear components under Axes, its temperature channels are
// Sensor components, and each value the server knows is one DataItem (docs/server.md, "MTConnect
// agent"). Ids are built from positions (m3_a1_pos), never from names, so any machine or channel
// name gives valid XML ids; names go into `name` attributes (escaped by pugixml).
//
//   Device   AVAILABILITY (EVENT)            AVAILABLE while the terminal answers
//            SYSTEM (CONDITION)              the compensator's alarms: Normal / Warning / Fault
//   Linear   POSITION ACTUAL (SAMPLE, MILLIMETER)          as the CNC reports it
//            x:COMPENSATION ACTUAL (SAMPLE, MILLIMETER)    the compensation the CNC applies now
//            x:COMPENSATION COMMANDED (SAMPLE, MILLIMETER) what the server last handed out
//            x:COMPENSATION_STATE (EVENT)                  full | fallback_model | geometric | disabled | link_lost
//   Sensor   TEMPERATURE (SAMPLE, CELSIUS)   the channel's reading
//            TEMPERATURE (CONDITION)         the channel's health: ok Normal, held Warning, lost Fault
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "trueaxis/server/shop.hpp"

namespace trueaxis::server::mtconnect {

inline constexpr const char* kVersion = "1.3.0";
inline constexpr const char* kDevicesUrn = "urn:mtconnect.org:MTConnectDevices:1.3";
inline constexpr const char* kStreamsUrn = "urn:mtconnect.org:MTConnectStreams:1.3";
inline constexpr const char* kErrorUrn = "urn:mtconnect.org:MTConnectError:1.3";
// The namespace of the x: extension types (x:COMPENSATION, x:COMPENSATION_STATE).
inline constexpr const char* kExtensionUrn = "urn:trueaxis:MTConnect:1.3";

enum class Category { kSample, kEvent, kCondition };

// Where a data item's value comes from in a MachineStatus.
enum class Source { kAvailability, kSystem, kPosition, kApplied, kCommanded, kAxisState, kTemperature, kChannelHealth };

struct DataItem {
  std::string id, name;
  std::string type;      // "POSITION", "x:COMPENSATION", ...
  std::string sub_type;  // "" none
  std::string units;     // "" none
  std::string element;   // its element in MTConnectStreams: "Position", "x:Compensation" (conditions: Normal/Warning/...)
  Category category = Category::kSample;
  Source source = Source::kAvailability;
  std::uint32_t device = 0;     // index in DeviceModel::devices
  std::uint32_t component = 0;  // index in that device's components
  std::uint32_t index = 0;      // the axis or channel
};

struct Component {
  std::string element;  // "Device", "Axes", "Linear", "Sensor"
  std::string id, name;
  int parent = -1;      // index of the enclosing component (-1: the Device itself)
  std::vector<std::uint32_t> items;  // DataItem indices
};

struct Device {
  std::string name, uuid;
  std::vector<Component> components;  // [0] is the Device
};

struct DeviceModel {
  std::vector<Device> devices;
  std::vector<DataItem> items;  // every device's, in document order
  // The device named `name_or_uuid`, or -1.
  int Find(const std::string& name_or_uuid) const;
};

// From the shop's machines as Shop::Snapshot() lists them (names, axes, channels).
DeviceModel BuildDeviceModel(const std::vector<MachineStatus>& machines);

// Text that may go into XML 1.0: control characters (other than tab and new line) become '?', at
// most `max_chars` bytes are kept (cut on a UTF-8 boundary).
std::string XmlSafe(const std::string& text, std::size_t max_chars = 200);

// "2026-11-29T02:00:00.123456Z"
std::string Iso8601(double unix_s);

}  // namespace trueaxis::server::mtconnect
