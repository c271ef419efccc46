// The MTConnect agent's observation buffer and documents, without a network: sequence numbers,
// the bounded ring and its checkpoint (/current?at=), /sample ranges and filters, and XML that
// stays well formed whatever a machine or channel is called.
#include <gtest/gtest.h>

#include <cctype>
#include <set>

#include <pugixml.hpp>

#include "trueaxis/server/mtconnect_buffer.hpp"
#include "trueaxis/server/mtconnect_devices.hpp"
#include "trueaxis/server/mtconnect_documents.hpp"

namespace trueaxis::server::mtconnect {
namespace {

std::vector<Observation> Batch(std::initializer_list<std::pair<std::uint32_t, const char*>> values) {
  std::vector<Observation> out;
  for (const auto& [item, value] : values) {
    Observation o;
    o.item = item;
    o.value = value;
    out.push_back(o);
  }
  return out;
}

std::vector<std::uint64_t> Sequences(const std::vector<Observation>& obs) {
  std::vector<std::uint64_t> s;
  for (const auto& o : obs) s.push_back(o.sequence);
  return s;
}

TEST(MtconnectBuffer, NumbersEveryObservationAndDropsTheOldestOnceFull) {
  ObservationBuffer buffer(4, 2);
  auto b1 = Batch({{0, "a1"}, {1, "b1"}, {0, "a2"}});
  buffer.Append(b1);
  EXPECT_EQ(Sequences(b1), (std::vector<std::uint64_t>{1, 2, 3}));
  BufferRange r = buffer.range();
  EXPECT_EQ(r.first, 1u);
  EXPECT_EQ(r.last, 3u);
  EXPECT_EQ(r.next, 4u);
  auto b2 = Batch({{1, "b2"}, {0, "a3"}, {0, "a4"}});  // 6 observations in a ring of 4: 1 and 2 leave
  buffer.Append(b2);
  r = buffer.range();
  EXPECT_EQ(r.first, 3u);
  EXPECT_EQ(r.last, 6u);
  EXPECT_EQ(r.next, 7u);

  std::vector<Observation> out;
  std::uint64_t next = 0;
  EXPECT_FALSE(buffer.Sample(2, 10, nullptr, out, &next, r)) << "from before firstSequence";
  EXPECT_FALSE(buffer.Sample(8, 10, nullptr, out, &next, r)) << "from after nextSequence";
  ASSERT_TRUE(buffer.Sample(3, 2, nullptr, out, &next, r));
  EXPECT_EQ(Sequences(out), (std::vector<std::uint64_t>{3, 4}));
  EXPECT_EQ(next, 5u);
  ASSERT_TRUE(buffer.Sample(next, 100, nullptr, out, &next, r));  // continues where the last one ended
  EXPECT_EQ(Sequences(out), (std::vector<std::uint64_t>{5, 6}));
  EXPECT_EQ(next, 7u);
  ASSERT_TRUE(buffer.Sample(next, 100, nullptr, out, &next, r));  // nothing new: empty, same nextSequence
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(next, 7u);
  ASSERT_TRUE(buffer.Sample(std::nullopt, 1, nullptr, out, &next, r));  // no `from`: the oldest held
  EXPECT_EQ(Sequences(out), (std::vector<std::uint64_t>{3}));
  const std::vector<bool> only_b = {false, true};
  ASSERT_TRUE(buffer.Sample(3, 100, &only_b, out, &next, r));
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].value, "b2");
  EXPECT_EQ(next, 7u);
}

TEST(MtconnectBuffer, CurrentHoldsEveryItemAndAtReplaysFromTheCheckpoint) {
  ObservationBuffer buffer(3, 3);  // item 2 never reports
  auto b = Batch({{0, "a1"}, {1, "b1"}, {0, "a2"}, {0, "a3"}, {0, "a4"}});  // b1 (2) leaves the ring
  buffer.Append(b);
  std::vector<Observation> out;
  BufferRange r;
  ASSERT_TRUE(buffer.Current(std::nullopt, nullptr, out, r));
  ASSERT_EQ(out.size(), 2u);  // the item that never reported is left out
  EXPECT_EQ(out[0].value, "a4");
  EXPECT_EQ(out[1].value, "b1") << "the latest value of an item stays after it left the ring";
  EXPECT_EQ(r.first, 3u);
  ASSERT_TRUE(buffer.Current(3, nullptr, out, r));
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].value, "a2");
  EXPECT_EQ(out[0].sequence, 3u);
  EXPECT_EQ(out[1].value, "b1");
  ASSERT_TRUE(buffer.Current(4, nullptr, out, r));
  EXPECT_EQ(out[0].value, "a3");
  EXPECT_FALSE(buffer.Current(2, nullptr, out, r)) << "at before firstSequence";
  EXPECT_FALSE(buffer.Current(6, nullptr, out, r)) << "at after lastSequence";
}

MachineStatus Machine(const std::string& name) {
  MachineStatus m;
  m.name = name;
  AxisView x;
  x.name = "X";
  m.axes.push_back(x);
  ChannelView c;
  c.name = "spindle<1>";
  m.channels.push_back(c);
  return m;
}

TEST(MtconnectDocuments, NamesAreEscapedAndIdsValidWhateverAMachineIsCalled) {
  const std::string odd = "a<b&\"c' \x01z";
  const DeviceModel model = BuildDeviceModel({Machine(odd), Machine("vmc-02")});
  ASSERT_EQ(model.devices.size(), 2u);
  EXPECT_EQ(model.Find("vmc-02"), 1);
  EXPECT_EQ(model.Find("trueaxis-vmc-02"), 1) << "by uuid";
  EXPECT_EQ(model.Find("nope"), -1);
  const HeaderInfo h{"host<&>", 7, 16, 1795000000.25};
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(DevicesDocument(model, h, -1).c_str()));
  const auto device = doc.child("MTConnectDevices").child("Devices").child("Device");
  EXPECT_EQ(std::string(device.attribute("name").value()), "a<b&\"c' ?z");
  EXPECT_EQ(std::string(doc.child("MTConnectDevices").child("Header").attribute("sender").value()), "host<&>");
  EXPECT_EQ(std::string(doc.child("MTConnectDevices").child("Header").attribute("creationTime").value()), "2026-11-18T11:06:40.250000Z");
  EXPECT_EQ(std::string(doc.child("MTConnectDevices").attribute("xmlns").value()), kDevicesUrn);
  // Ids: XML names (a letter first), unique, none made from the machine's name.
  std::set<std::string> ids;
  for (const auto& n : doc.select_nodes("//*[@id]")) {
    const std::string id = n.node().attribute("id").value();
    EXPECT_TRUE(std::isalpha(static_cast<unsigned char>(id[0]))) << id;
    EXPECT_EQ(id.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_"), std::string::npos) << id;
    EXPECT_TRUE(ids.insert(id).second) << id;
  }
  EXPECT_EQ(ids.size(), 2u * (1 + 2 + 1 + 1 + 4 + 1 + 2));  // Device + 2 items, Axes, Linear + 4, Sensor + 2
  EXPECT_EQ(std::string(doc.select_node("//Sensor/DataItems/DataItem[@type='TEMPERATURE' and @category='SAMPLE']")
                            .node().attribute("units").value()),
            "CELSIUS");

  // Streams: one ComponentStream per component, Samples before Events before Condition.
  std::vector<Observation> obs(4);
  const std::uint32_t avail = model.devices[0].components[0].items[0], system = model.devices[0].components[0].items[1];
  const std::uint32_t pos = model.devices[0].components[2].items[0], state = model.devices[0].components[2].items[3];
  obs[0] = {5, system, 1795000000, "Fault", "link_read", "link_read: <timeout> & more"};
  obs[1] = {3, avail, 1795000000, "UNAVAILABLE", "", ""};
  obs[2] = {6, state, 1795000000, "link_lost", "", ""};
  obs[3] = {4, pos, 1795000000, "12.5000", "", ""};
  pugi::xml_document streams;
  ASSERT_TRUE(streams.load_string(StreamsDocument(model, h, {1, 6, 7, 16}, 7, obs, 0).c_str()));
  const auto header = streams.child("MTConnectStreams").child("Header");
  EXPECT_EQ(header.attribute("nextSequence").as_ullong(), 7u);
  EXPECT_EQ(header.attribute("firstSequence").as_ullong(), 1u);
  EXPECT_EQ(header.attribute("lastSequence").as_ullong(), 6u);
  const auto ds = streams.child("MTConnectStreams").child("Streams").child("DeviceStream");
  EXPECT_EQ(std::string(ds.attribute("name").value()), "a<b&\"c' ?z");
  EXPECT_FALSE(ds.next_sibling()) << "one device asked for";
  auto cs = ds.child("ComponentStream");
  EXPECT_EQ(std::string(cs.attribute("component").value()), "Device");
  EXPECT_EQ(std::string(cs.first_child().name()), "Events");
  EXPECT_EQ(std::string(cs.last_child().name()), "Condition");
  const auto fault = cs.child("Condition").child("Fault");
  EXPECT_EQ(std::string(fault.attribute("type").value()), "SYSTEM");
  EXPECT_EQ(std::string(fault.attribute("nativeCode").value()), "link_read");
  EXPECT_EQ(std::string(fault.text().get()), "link_read: <timeout> & more");
  cs = cs.next_sibling("ComponentStream");
  EXPECT_EQ(std::string(cs.attribute("component").value()), "Linear");
  EXPECT_EQ(std::string(cs.first_child().name()), "Samples");
  EXPECT_EQ(std::string(cs.child("Samples").child("Position").attribute("subType").value()), "ACTUAL");
  EXPECT_EQ(std::string(cs.child("Events").child("x:CompensationState").text().get()), "link_lost");

  pugi::xml_document error;
  ASSERT_TRUE(error.load_string(ErrorDocument(h, "NO_DEVICE", "no device named '<script>&'").c_str()));
  const auto e = error.child("MTConnectError").child("Errors").child("Error");
  EXPECT_EQ(std::string(e.attribute("errorCode").value()), "NO_DEVICE");
  EXPECT_EQ(std::string(e.text().get()), "no device named '<script>&'");
}

TEST(MtconnectDocuments, XmlSafeCutsOnACharacterBoundary) {
  EXPECT_EQ(XmlSafe("abc\x02\x1b\td", 200), "abc??\td");
  EXPECT_EQ(XmlSafe("ab\xc3\xa9", 3), "ab") << "é cut in half is dropped whole";
  EXPECT_EQ(XmlSafe("ab\xc3\xa9", 4), "ab\xc3\xa9");
}

}  // namespace
}  // namespace trueaxis::server::mtconnect
