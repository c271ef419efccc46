// Golden files for the fixed example model (tests/export/golden/), reviewed
// against the syntax examples of each controller's manual (docs/export.md).
// Regenerate after an intended change with TRUEAXIS_UPDATE_GOLDEN=1 and
// review the diff.
#include <cstdlib>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "example_model.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/export/csv_table.hpp"
#include "trueaxis/export/fanuc_table.hpp"
#include "trueaxis/export/heidenhain_table.hpp"
#include "trueaxis/export/linuxcnc_table.hpp"
#include "trueaxis/export/resample.hpp"
#include "trueaxis/export/sinumerik_table.hpp"
#include "trueaxis/model/model_json.hpp"

namespace trueaxis::exporter {
namespace {

const std::string kGolden = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/export/golden/";

void ExpectGolden(const std::string& name, const std::string& text) {
  const std::string path = kGolden + name;
  if (std::getenv("TRUEAXIS_UPDATE_GOLDEN")) {
    WriteTextFile(path, text);
    return;
  }
  ASSERT_TRUE(std::filesystem::exists(path)) << path << " missing; run with TRUEAXIS_UPDATE_GOLDEN=1";
  EXPECT_EQ(ReadTextFile(path), text) << "golden file " << path << " differs";
}

ResampleOptions Golden(bool bidirectional, bool thermal_in_table = true) {
  ResampleOptions o;
  o.spacing_mm = 50;
  o.bidirectional = bidirectional;
  o.thermal.temperatures_c = {{"nut", 30}, {"bearing", 26}};
  o.thermal_in_table = thermal_in_table;
  return o;
}

TEST(Golden, ModelFileForTheCli) {
  // The CLI tests and docs/export.md use this model file.
  ExpectGolden("example_model.json", model::ModelToJson(testing::ExampleModel()).dump(2) + "\n");
}

TEST(Golden, LinuxCnc) {
  const auto r = ResampleModel(testing::ExampleAxis(), Golden(true), "example_model.json");
  LinuxCncOptions o;
  o.comp_file_name = "x_comp.txt";
  ExpectGolden("x_comp_type1.txt", WriteLinuxCncCompFile(r.table, o, "t"));
  ExpectGolden("x_comp_type1.ini", LinuxCncIniSnippet(r.table, o));
  o.comp_file_type = 0;
  ExpectGolden("x_comp_type0.txt", WriteLinuxCncCompFile(r.table, o, "t"));
}

TEST(Golden, Sinumerik) {
  const auto r = ResampleModel(testing::ExampleAxis(), Golden(false, false), "example_model.json");
  ExpectGolden("X_EEC.INI", WriteSinumerikEec(r.table, {}, "t"));
}

TEST(Golden, Fanuc) {
  auto o = Golden(true);
  o.zero_at_reference = true;
  const auto r = ResampleModel(testing::ExampleAxis(), o, "example_model.json");
  const auto res = WriteFanucPitchTape(r.table, {}, "t");
  ExpectGolden("x_pitch_fanuc.txt", res.tape);
}

TEST(Golden, HeidenhainAndCsv) {
  const auto r = ResampleModel(testing::ExampleAxis(), Golden(true), "example_model.json");
  ExpectGolden("X_OFF.COM", WriteHeidenhainCom(r.table, "X_OFF.COM", ValueSign::kCorrection, "t"));
  ExpectGolden("X.CMA", WriteHeidenhainCma("X", "X.CMA",
                                           {{"X_COLD.COM", false, "cold state, coolant off"},
                                            {"X_OFF.COM", true, "coolant off, nut=30 bearing=26"},
                                            {"X_FLOOD.COM", false, "coolant flood, nut=30 bearing=26"}},
                                           "t"));
  ExpectGolden("x_table.csv", WriteCsvTable(r.table, ValueSign::kCorrection, "t"));
}

}  // namespace
}  // namespace trueaxis::exporter
