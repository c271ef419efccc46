// The campaign manifest shared by `sim campaign`, `campaign plan/add/check` and the fit: what is
// written is read back the same, the former format name is still read, and bad entries are refused
// naming the field.
#include "trueaxis/measure/campaign_manifest.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::measure {
namespace {

CampaignManifest Sample() {
  CampaignManifest m;
  m.machine = "VMC-850 #3";
  m.machine_file = "machine.toml";
  m.start_date = "2026-03-02T07:00:00";
  m.axes = {"X", "Z"};
  m.sensors = {"x_nut", "x_nut_b", "room"};
  m.sensor_locations = {{"x_nut_b", "x_nut"}, {"room", "ambient"}};
  CampaignEntry e;
  e.file = "X_01_cold.csv";
  e.axis = "X";
  e.state = "cold";
  e.sequence = 1;
  e.start_time_s = 3.04;
  e.end_time_s = 1307.9;
  e.nut_rise_c = 0;
  e.mean_temperatures_c = {{"x_nut", 15.6374}, {"x_nut_b", std::nan("")}, {"room", 16.2}};
  m.measurements.push_back(e);
  e.file = "X_02_coolant_01.csv";
  e.state = "coolant";
  e.coolant = "flood";
  e.coolant_session = 1;
  e.start_time_s = std::nan("");  // not yet stamped: written as null
  m.measurements.push_back(e);
  return m;
}

TEST(CampaignManifest, WrittenIsReadBack) {
  const std::string text = CampaignManifestJson(Sample());
  EXPECT_NE(text.find("\"format\": \"trueaxis-campaign\""), std::string::npos);
  const auto m = ParseCampaignManifest(text, "manifest.json");
  ASSERT_EQ(m.measurements.size(), 2u);
  EXPECT_EQ(m.machine, "VMC-850 #3");
  EXPECT_EQ(m.axes, (std::vector<std::string>{"X", "Z"}));
  EXPECT_EQ(m.measurements[0].state, "cold");
  EXPECT_DOUBLE_EQ(m.measurements[0].start_time_s, 3.0);  // rounded to 0.1 s
  EXPECT_DOUBLE_EQ(m.measurements[0].MeanTemperatureC("x_nut"), 15.637);
  EXPECT_TRUE(std::isnan(m.measurements[0].MeanTemperatureC("x_nut_b")));
  EXPECT_TRUE(std::isnan(m.measurements[1].start_time_s));
  EXPECT_EQ(m.measurements[1].coolant, "flood");
  EXPECT_EQ(m.measurements[1].coolant_session, 1);
  // Locations: two probes on the X nut, the room sensor by its location.
  EXPECT_EQ(m.SensorsAt("x_nut"), (std::vector<std::string>{"x_nut", "x_nut_b"}));
  EXPECT_EQ(m.NutSensor("X"), "x_nut");
  EXPECT_EQ(m.SensorsAt("ambient"), (std::vector<std::string>{"room"}));
  EXPECT_EQ(m.NutSensor("Z"), "");
  // And written again, byte for byte.
  EXPECT_EQ(CampaignManifestJson(m), text);
}

TEST(CampaignManifest, FormerSimNameIsRead) {
  std::string text = CampaignManifestJson(Sample());
  text.replace(text.find("trueaxis-campaign"), std::string("trueaxis-campaign").size(), "trueaxis-sim-campaign");
  const auto m = ParseCampaignManifest(text, "manifest.json");
  EXPECT_EQ(m.format, "trueaxis-sim-campaign");
  EXPECT_NE(CampaignManifestJson(m).find("\"trueaxis-campaign\""), std::string::npos);
}

void ExpectRefused(const std::string& text, const std::string& field) {
  try {
    ParseCampaignManifest(text, "m.json");
    FAIL() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), "m.json");
    EXPECT_EQ(e.field(), field) << e.what();
  }
}

TEST(CampaignManifest, BadInputNamesTheField) {
  ExpectRefused(R"({"format": "other", "version": 1, "measurements": []})", "format");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 2, "measurements": []})", "version");
  ExpectRefused(R"({"measurements": []})", "format");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1})", "measurements");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1, "measurements": [{"file": "a.csv", "axis": "X",
                "state": "hot"}]})", "measurements[0].state");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1, "measurements": [{"file": "a.csv", "axis": "X",
                "state": "cold", "coolant": "oil"}]})", "measurements[0].coolant");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1, "measurements": [{"file": "a.csv", "state": "cold"}]})",
                "measurements[0].axis");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1, "measurements": [{"file": "a.csv", "axis": "X",
                "state": "cold", "start_time_s": "soon"}]})", "measurements[0].start_time_s");
  ExpectRefused(R"({"format": "trueaxis-campaign", "version": 1, "sensors": ["a"], "sensor_locations": {"b": "x_nut"},
                "measurements": []})", "sensor_locations.b");
}

TEST(CampaignManifest, LogHeaderHasTheFitsColumns) {
  EXPECT_EQ(CampaignLogHeader({"X", "Y"}, {"x_nut", "ambient"}),
            "time_s,date,coolant,x_mm,y_mm,x_travel_mm,y_travel_mm,t_x_nut_c,t_ambient_c\n");
}

}  // namespace
}  // namespace trueaxis::measure
