#include "trueaxis/server/mtconnect_documents.hpp"

#include <algorithm>
#include <sstream>

#include <pugixml.hpp>

namespace trueaxis::server::mtconnect {
namespace {

pugi::xml_node Root(pugi::xml_document& doc, const char* name, const char* urn, const char* xsd, bool extension) {
  auto decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  pugi::xml_node root = doc.append_child(name);
  root.append_attribute("xmlns") = urn;
  if (extension) root.append_attribute("xmlns:x") = kExtensionUrn;
  root.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
  root.append_attribute("xsi:schemaLocation") = (std::string(urn) + " http://schemas.mtconnect.org/schemas/" + xsd).c_str();
  return root;
}

pugi::xml_node Header(pugi::xml_node root, const HeaderInfo& h) {
  pugi::xml_node n = root.append_child("Header");
  n.append_attribute("creationTime") = Iso8601(h.now_unix_s).c_str();
  n.append_attribute("sender") = h.sender.c_str();
  n.append_attribute("instanceId") = static_cast<unsigned long long>(h.instance_id);
  n.append_attribute("version") = kVersion;
  n.append_attribute("bufferSize") = static_cast<unsigned long long>(h.buffer_size);
  return n;
}

std::string Text(const pugi::xml_document& doc) {
  std::ostringstream os;
  doc.save(os, "  ", pugi::format_indent, pugi::encoding_utf8);
  return os.str();
}

const char* CategoryName(Category c) {
  switch (c) {
    case Category::kSample: return "SAMPLE";
    case Category::kEvent: return "EVENT";
    case Category::kCondition: return "CONDITION";
  }
  return "EVENT";
}

void DataItems(pugi::xml_node parent, const DeviceModel& model, const Component& c) {
  if (c.items.empty()) return;
  pugi::xml_node items = parent.append_child("DataItems");
  for (std::uint32_t i : c.items) {
    const DataItem& d = model.items[i];
    pugi::xml_node n = items.append_child("DataItem");
    n.append_attribute("category") = CategoryName(d.category);
    n.append_attribute("id") = d.id.c_str();
    n.append_attribute("name") = d.name.c_str();
    n.append_attribute("type") = d.type.c_str();
    if (!d.sub_type.empty()) n.append_attribute("subType") = d.sub_type.c_str();
    if (!d.units.empty()) {
      n.append_attribute("units") = d.units.c_str();
      n.append_attribute("nativeUnits") = d.units.c_str();
    }
    if (d.type == "POSITION") n.append_attribute("coordinateSystem") = "MACHINE";  // as the CNC reports it
  }
}

void Components(pugi::xml_node parent, const DeviceModel& model, const Device& device, int of) {
  pugi::xml_node list;
  for (std::size_t k = 0; k < device.components.size(); ++k) {
    const Component& c = device.components[k];
    if (c.parent != of) continue;
    if (!list) list = parent.append_child("Components");
    pugi::xml_node n = list.append_child(c.element.c_str());
    n.append_attribute("id") = c.id.c_str();
    n.append_attribute("name") = c.name.c_str();
    DataItems(n, model, c);
    Components(n, model, device, static_cast<int>(k));
  }
}

}  // namespace

void BuildDevices(const DeviceModel& model, const HeaderInfo& header, int device, pugi::xml_document& doc) {
  pugi::xml_node root = Root(doc, "MTConnectDevices", kDevicesUrn, "MTConnectDevices_1.3.xsd", true);
  pugi::xml_node h = Header(root, header);
  h.append_attribute("assetBufferSize") = 1;
  h.append_attribute("assetCount") = 0;
  pugi::xml_node devices = root.append_child("Devices");
  for (std::size_t d = 0; d < model.devices.size(); ++d) {
    if (device >= 0 && static_cast<int>(d) != device) continue;
    const Device& dev = model.devices[d];
    const Component& self = dev.components.front();
    pugi::xml_node n = devices.append_child("Device");
    n.append_attribute("id") = self.id.c_str();
    n.append_attribute("name") = dev.name.c_str();
    n.append_attribute("uuid") = dev.uuid.c_str();
    n.append_child("Description").text() = "A machine tool of the workshop server: positions, temperatures and the thermal compensation trueaxis applies";
    DataItems(n, model, self);
    Components(n, model, dev, 0);
  }
}

std::string DevicesDocument(const DeviceModel& model, const HeaderInfo& header, int device) {
  pugi::xml_document doc;
  BuildDevices(model, header, device, doc);
  return Text(doc);
}

std::string StreamsDocument(const DeviceModel& model, const HeaderInfo& header, const BufferRange& range, std::uint64_t next_sequence,
                            std::vector<Observation> observations, int device) {
  pugi::xml_document doc;
  pugi::xml_node root = Root(doc, "MTConnectStreams", kStreamsUrn, "MTConnectStreams_1.3.xsd", true);
  pugi::xml_node h = Header(root, header);
  h.append_attribute("nextSequence") = static_cast<unsigned long long>(next_sequence);
  h.append_attribute("firstSequence") = static_cast<unsigned long long>(range.first);
  h.append_attribute("lastSequence") = static_cast<unsigned long long>(range.last);
  pugi::xml_node streams = root.append_child("Streams");
  // Device, then component, then sequence: one ComponentStream per component, its values in order.
  std::stable_sort(observations.begin(), observations.end(), [&](const Observation& a, const Observation& b) {
    const DataItem& x = model.items[a.item];
    const DataItem& y = model.items[b.item];
    if (x.device != y.device) return x.device < y.device;
    if (x.component != y.component) return x.component < y.component;
    return a.sequence < b.sequence;
  });
  std::size_t o = 0;
  for (std::size_t d = 0; d < model.devices.size(); ++d) {
    if (device >= 0 && static_cast<int>(d) != device) continue;
    const Device& dev = model.devices[d];
    pugi::xml_node ds = streams.append_child("DeviceStream");
    ds.append_attribute("name") = dev.name.c_str();
    ds.append_attribute("uuid") = dev.uuid.c_str();
    while (o < observations.size() && model.items[observations[o].item].device < d) ++o;
    while (o < observations.size() && model.items[observations[o].item].device == d) {
      const Component& c = dev.components[model.items[observations[o].item].component];
      pugi::xml_node cs = ds.append_child("ComponentStream");
      cs.append_attribute("component") = c.element.c_str();
      cs.append_attribute("name") = c.name.c_str();
      cs.append_attribute("componentId") = c.id.c_str();
      pugi::xml_node samples, events, condition;  // in this order, as the schema wants them
      const std::size_t begin = o;
      const std::uint32_t component = model.items[observations[o].item].component;
      for (; o < observations.size() && model.items[observations[o].item].device == d &&
             model.items[observations[o].item].component == component;
           ++o) {
        const DataItem& item = model.items[observations[o].item];
        if (item.category == Category::kSample && !samples) samples = cs.append_child("Samples");
        if (item.category == Category::kEvent && !events) events = cs.append_child("Events");
        if (item.category == Category::kCondition && !condition) condition = cs.append_child("Condition");
      }
      if (samples && events) cs.insert_move_before(samples, events);
      if (condition) cs.append_move(condition);
      for (std::size_t k = begin; k < o; ++k) {
        const Observation& ob = observations[k];
        const DataItem& item = model.items[ob.item];
        pugi::xml_node parent = item.category == Category::kSample ? samples : item.category == Category::kEvent ? events : condition;
        pugi::xml_node n = parent.append_child(item.category == Category::kCondition ? ob.value.c_str() : item.element.c_str());
        n.append_attribute("dataItemId") = item.id.c_str();
        n.append_attribute("timestamp") = Iso8601(ob.time_unix_s).c_str();
        n.append_attribute("name") = item.name.c_str();
        n.append_attribute("sequence") = static_cast<unsigned long long>(ob.sequence);
        if (!item.sub_type.empty()) n.append_attribute("subType") = item.sub_type.c_str();
        if (item.category == Category::kCondition) {
          n.append_attribute("type") = item.type.c_str();
          if (!ob.native_code.empty()) n.append_attribute("nativeCode") = ob.native_code.c_str();
          if (!ob.text.empty()) n.text() = ob.text.c_str();
        } else {
          n.text() = ob.value.c_str();
        }
      }
    }
  }
  return Text(doc);
}

std::string ErrorDocument(const HeaderInfo& header, const std::string& error_code, const std::string& message) {
  pugi::xml_document doc;
  pugi::xml_node root = Root(doc, "MTConnectError", kErrorUrn, "MTConnectError_1.3.xsd", false);
  Header(root, header);
  pugi::xml_node e = root.append_child("Errors").append_child("Error");
  e.append_attribute("errorCode") = error_code.c_str();
  e.text() = XmlSafe(message, 400).c_str();
  return Text(doc);
}

}  // namespace trueaxis::server::mtconnect
