#include "trueaxis/server/mtconnect_devices.hpp"

#include <cmath>
#include <ctime>

#include <fmt/format.h>

namespace trueaxis::server::mtconnect {

int DeviceModel::Find(const std::string& name_or_uuid) const {
  for (std::size_t d = 0; d < devices.size(); ++d)
    if (devices[d].name == name_or_uuid || devices[d].uuid == name_or_uuid) return static_cast<int>(d);
  return -1;
}

namespace {

struct Builder {
  DeviceModel& model;
  std::uint32_t device;

  std::uint32_t AddComponent(std::string element, std::string id, std::string name, int parent) {
    Device& d = model.devices[device];
    d.components.push_back({std::move(element), std::move(id), XmlSafe(name), parent, {}});
    return static_cast<std::uint32_t>(d.components.size() - 1);
  }

  void AddItem(std::uint32_t component, std::string id, std::string name, Category category, std::string type, std::string sub_type,
               std::string units, std::string element, Source source, std::uint32_t index) {
    DataItem item;
    item.id = std::move(id);
    item.name = XmlSafe(name);
    item.category = category;
    item.type = std::move(type);
    item.sub_type = std::move(sub_type);
    item.units = std::move(units);
    item.element = std::move(element);
    item.source = source;
    item.device = device;
    item.component = component;
    item.index = index;
    model.devices[device].components[component].items.push_back(static_cast<std::uint32_t>(model.items.size()));
    model.items.push_back(std::move(item));
  }
};

}  // namespace

DeviceModel BuildDeviceModel(const std::vector<MachineStatus>& machines) {
  DeviceModel model;
  for (std::size_t m = 0; m < machines.size(); ++m) {
    const MachineStatus& s = machines[m];
    const std::string id = fmt::format("m{}", m);
    model.devices.push_back({XmlSafe(s.name), XmlSafe("trueaxis-" + s.name), {}});
    Builder b{model, static_cast<std::uint32_t>(m)};
    const std::uint32_t dev = b.AddComponent("Device", id, s.name, -1);
    b.AddItem(dev, id + "_avail", "availability", Category::kEvent, "AVAILABILITY", "", "", "Availability", Source::kAvailability, 0);
    b.AddItem(dev, id + "_system", "alarms", Category::kCondition, "SYSTEM", "", "", "", Source::kSystem, 0);
    if (!s.axes.empty()) {
      const std::uint32_t axes = b.AddComponent("Axes", id + "_axes", "base", 0);
      for (std::size_t a = 0; a < s.axes.size(); ++a) {
        const std::string aid = fmt::format("{}_a{}", id, a);
        const std::string& n = s.axes[a].name;
        const std::uint32_t c = b.AddComponent("Linear", aid, n, static_cast<int>(axes));
        const auto i = static_cast<std::uint32_t>(a);
        b.AddItem(c, aid + "_pos", n + "_position", Category::kSample, "POSITION", "ACTUAL", "MILLIMETER", "Position", Source::kPosition, i);
        b.AddItem(c, aid + "_comp", n + "_compensation", Category::kSample, "x:COMPENSATION", "ACTUAL", "MILLIMETER", "x:Compensation",
                  Source::kApplied, i);
        b.AddItem(c, aid + "_comp_cmd", n + "_compensation_commanded", Category::kSample, "x:COMPENSATION", "COMMANDED", "MILLIMETER",
                  "x:Compensation", Source::kCommanded, i);
        b.AddItem(c, aid + "_state", n + "_compensation_state", Category::kEvent, "x:COMPENSATION_STATE", "", "",
                  "x:CompensationState", Source::kAxisState, i);
      }
    }
    for (std::size_t k = 0; k < s.channels.size(); ++k) {
      const std::string cid = fmt::format("{}_c{}", id, k);
      const std::string& n = s.channels[k].name;
      const std::uint32_t c = b.AddComponent("Sensor", cid, n, 0);
      const auto i = static_cast<std::uint32_t>(k);
      b.AddItem(c, cid + "_temp", n + "_temperature", Category::kSample, "TEMPERATURE", "", "CELSIUS", "Temperature", Source::kTemperature, i);
      b.AddItem(c, cid + "_health", n + "_health", Category::kCondition, "TEMPERATURE", "", "", "", Source::kChannelHealth, i);
    }
  }
  return model;
}

std::string XmlSafe(const std::string& text, std::size_t max_chars) {
  std::string out = text.substr(0, max_chars);
  auto continuation = [](char c) { return (static_cast<unsigned char>(c) & 0xC0) == 0x80; };
  if (out.size() < text.size() && continuation(text[out.size()])) {  // cut inside a character: drop all of it
    while (!out.empty() && continuation(out.back())) out.pop_back();
    if (!out.empty()) out.pop_back();
  }
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') c = '?';
  return out;
}

std::string Iso8601(double unix_s) {
  const double whole = std::floor(unix_s);
  const auto t = static_cast<std::time_t>(whole);
  auto micro = static_cast<long>(std::lround((unix_s - whole) * 1e6));
  std::time_t secs = t;
  if (micro >= 1000000) {
    micro -= 1000000;
    ++secs;
  }
  std::tm tm{};
  gmtime_r(&secs, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:06}Z", tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min,
                     tm.tm_sec, micro);
}

}  // namespace trueaxis::server::mtconnect
