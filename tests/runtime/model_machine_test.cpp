// A model fitted on another machine (a lathe's model on the VMC-850) was bound and run without a
// word; station::PublishModelFile now refuses it — at start and on a reload, which keeps the
// running model — naming the config's [model] file line and both machine names.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "trueaxis/core/input_error.hpp"
#include "trueaxis/model/composite_model.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/runtime/compensator.hpp"
#include "trueaxis/station/site_config.hpp"
#include "trueaxis/station/model_loading.hpp"

namespace trueaxis::station {
namespace {
namespace fs = std::filesystem;

model::CompositeModel XModel(const std::string& machine, const std::string& axis = "X") {
  model::CompositeModel m;
  m.machine = machine;
  model::AxisModel a;
  a.axis = axis;
  a.key_sensors = {"x_nut"};
  a.baseline_temp_c = {20};
  for (auto& d : a.directions) {
    d.geometric.center_mm = 400;
    d.geometric.half_span_mm = 400;
    d.geometric.coefficients_um = {-20, -15};
    d.thermal = {{CoolantState::kOff, {-0.01}, 0}};
  }
  m.axes.push_back(a);
  return m;
}

TEST(ModelMachine, MismatchNamesBothMachinesOrTheMissingAxis) {
  EXPECT_FALSE(ModelMachineMismatch(XModel("VMC-850"), "VMC-850", {"X", "Y", "Z"}));
  EXPECT_FALSE(ModelMachineMismatch(XModel("vmc-850"), "VMC-850", {"X", "Y", "Z"}));  // one machine, any case
  EXPECT_FALSE(ModelMachineMismatch(XModel(""), "VMC-850", {"X"}));   // a model without a name: not compared
  EXPECT_FALSE(ModelMachineMismatch(XModel("TC-620"), "", {"X"}));    // a machine without a name: not compared
  const auto other = ModelMachineMismatch(XModel("TC-620"), "VMC-850", {"X", "Y", "Z"});
  ASSERT_TRUE(other);
  EXPECT_NE(other->find("'TC-620'"), std::string::npos) << *other;
  EXPECT_NE(other->find("'VMC-850'"), std::string::npos) << *other;
  const auto axis = ModelMachineMismatch(XModel("VMC-850", "A"), "VMC-850", {"X", "Y", "Z"});
  ASSERT_TRUE(axis);
  EXPECT_NE(axis->find("axis 'A'"), std::string::npos) << *axis;
}

TEST(ModelMachine, PublishRefusesAModelOfAnotherMachineNamingTheConfigLine) {
  const fs::path dir = fs::temp_directory_path() / ("trueaxis_model_machine_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string config_text = "[machine]\nkind = \"modbus\"\nname = \"VMC-850\"\naxes = [\"X\", \"Z\"]\n"
                                  "channels = [\"x_nut\"]\n[model]\nfile = \"model.json\"\n";
  const std::string source = (dir / "run.toml").string();
  const SiteConfig site = ParseSiteConfig(config_text, source);
  const InstallationConfig& c = site.installation;
  EXPECT_EQ(site.modbus.machine_name, "VMC-850");
  runtime::Compensator comp(runtime::CompensatorOptions{}, {runtime::AxisInterface{"X"}, runtime::AxisInterface{"Z"}},
                            {"x_nut"});

  model::WriteModelFile(XModel("VMC-850"), (dir / "model.json").string());
  EXPECT_NO_THROW(PublishModelFile(comp, c, site.modbus.machine_name));

  model::WriteModelFile(XModel("TC-620"), (dir / "model.json").string());  // the reload of a lathe's model
  try {
    PublishModelFile(comp, c, site.modbus.machine_name);
    ADD_FAILURE() << "a model of machine TC-620 was published on VMC-850";
  } catch (const InputError& e) {
    EXPECT_EQ(e.source(), source);
    EXPECT_EQ(e.line(), 7) << e.what();
    EXPECT_EQ(e.field(), "model.file") << e.what();
    EXPECT_NE(std::string(e.what()).find("'TC-620'"), std::string::npos) << e.what();
  }

  model::WriteModelFile(XModel("VMC-850", "Y"), (dir / "model.json").string());  // the machine has no Y
  try {
    PublishModelFile(comp, c, site.modbus.machine_name);
    ADD_FAILURE() << "a model of axis Y was published on a machine with X and Z";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "model.file") << e.what();
    EXPECT_NE(std::string(e.what()).find("axis 'Y'"), std::string::npos) << e.what();
  }

  fs::remove(dir / "model.json");
  try {
    PublishModelFile(comp, c, site.modbus.machine_name);
    ADD_FAILURE() << "a missing model file was not refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.line(), 7) << e.what();
    EXPECT_EQ(e.field(), "model.file") << e.what();
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace trueaxis::station
