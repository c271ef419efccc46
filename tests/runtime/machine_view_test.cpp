// runtime::MachineViewJson, the one writer of a machine's live state for both HTTP servers: every
// field with its unit in the name, values not known now as null (never a stale or made-up number).
#include "trueaxis/runtime/machine_view.hpp"

#include <gtest/gtest.h>

namespace trueaxis::runtime {
namespace {

TEST(MachineView, WritesEveryFieldAndUnknownValuesAsNull) {
  MachineView m;
  m.id = "vmc850";
  m.name = "VMC 850";
  m.connected = true;
  m.updated_unix_s = 1795000000.5;
  m.alarms = SplitAlarmNames("sensor_held|model_extrapolated");
  m.coolant = "flood";
  m.model = {"3", "ab12", "/srv/model.json"};
  m.axes.push_back({"X", true, "full", 412.5, -12.4, -12.6, kUnknown});
  m.channels.push_back({"x_nut", 27.41, "ok"});
  m.channels.push_back({"bed", kUnknown, "lost"});
  const auto j = MachineViewJson(m);
  EXPECT_EQ(j["id"], "vmc850");
  EXPECT_EQ(j["name"], "VMC 850");
  EXPECT_TRUE(j["connected"].get<bool>());
  EXPECT_DOUBLE_EQ(j["updated_unix_s"].get<double>(), 1795000000.5);
  EXPECT_EQ(j["alarms"], nlohmann::json({"sensor_held", "model_extrapolated"}));
  EXPECT_EQ(j["coolant"], "flood");
  EXPECT_TRUE(j["coolant_override"].is_null());
  EXPECT_EQ(j["model"], nlohmann::json({{"revision", "3"}, {"sha256", "ab12"}, {"file", "/srv/model.json"}}));
  const auto& x = j["axes"][0];
  EXPECT_EQ(x["name"], "X");
  EXPECT_TRUE(x["enabled"].get<bool>());
  EXPECT_EQ(x["state"], "full");
  EXPECT_DOUBLE_EQ(x["position_mm"].get<double>(), 412.5);
  EXPECT_DOUBLE_EQ(x["correction_um"].get<double>(), -12.4);
  EXPECT_DOUBLE_EQ(x["target_um"].get<double>(), -12.6);
  EXPECT_TRUE(x["applied_um"].is_null());
  EXPECT_EQ(j["channels"][0], nlohmann::json({{"name", "x_nut"}, {"temp_c", 27.41}, {"health", "ok"}}));
  EXPECT_TRUE(j["channels"][1]["temp_c"].is_null());

  m.coolant_override = "mist";
  m.updated_unix_s = kUnknown;  // never read
  const auto k = MachineViewJson(m);
  EXPECT_EQ(k["coolant_override"], "mist");
  EXPECT_TRUE(k["updated_unix_s"].is_null());
}

TEST(MachineView, SplitsAlarmNamesAndNoneIsEmpty) {
  EXPECT_TRUE(SplitAlarmNames("").empty());
  EXPECT_EQ(SplitAlarmNames("link_read"), std::vector<std::string>{"link_read"});
  EXPECT_EQ(SplitAlarmNames("link_read|no_model_for_axis(Y)"),
            (std::vector<std::string>{"link_read", "no_model_for_axis(Y)"}));
}

}  // namespace
}  // namespace trueaxis::runtime
