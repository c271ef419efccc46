// RunBackend: one machine under `trueaxis run` seen and operated through the web backend — a
// compensator on mock hardware, its cycle records handed over as the run's loop does, history in
// a real history database.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <unistd.h>

#include <gtest/gtest.h>

#include "store/test_dir.hpp"
#include "support/mock_hardware.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/runtime/cycle_recorder.hpp"
#include "trueaxis/station/history_logger.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/station/model_loading.hpp"
#include "trueaxis/web/run_backend.hpp"

namespace trueaxis::web {
namespace {

namespace fs = std::filesystem;
const Actor kWho{"op", "127.0.0.1:5000"};

class RunBackendTest : public trueaxis::testing::TempDirTest {
 protected:
  void SetUp() override {
    TempDirTest::SetUp();
    comp_ = runtime::Compensator::ForHardware(runtime::CompensatorOptions{}, link_, temps_, {});
    model_ = std::make_shared<const model::CompositeModel>(
        model::ReadModelFile(std::string(TRUEAXIS_SOURCE_DIR) + "/tests/export/golden/example_model.json"));
    comp_->PublishModel(model_, "example_model.json");
    writer_ = std::make_unique<store::HistoryWriter>((dir_ / "history.sqlite").string());
    unix0_ = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    logger_ = std::make_unique<station::HistoryLogger>(*writer_, std::vector<std::string>{"X"},
                                                       std::vector<std::string>{"nut", "bearing"}, unix0_);
    RunBackendOptions o;
    o.machine_id = "vmc1";
    o.history_db = (dir_ / "history.sqlite").string();
    o.unix0 = unix0_;
    backend_ = std::make_unique<RunBackend>(*comp_, &link_, writer_.get(), o);
    backend_->OnModelPublished({std::to_string(model_->revision), model_, {}}, "aa", "example_model.json", unix0_);
    cnc_.axes[0].position_mm = 200;
    cnc_.axes[0].servo_direction = 1;
  }
  void TearDown() override {
    writer_.reset();
    TempDirTest::TearDown();
  }
  // `n` cycles of 10 ms, every 10th handed to the backend and the history (as the run's recorder does).
  runtime::CycleRecord Cycles(int n) {
    runtime::CycleRecord rec;
    for (int i = 0; i < n; ++i) {
      const auto& s = comp_->RunCycle(link_, temps_, t_ += 0.01);
      if (++cycle_ % 10 == 0) {
        runtime::FillRecord(s, rec);
        backend_->OnRecord(rec);
        logger_->Log(rec);
      }
    }
    return rec;
  }

  trueaxis::testing::MockCnc cnc_{{"X"}};
  trueaxis::testing::MockTemperatures temps_{{"nut", "bearing"}, 20.0};
  CoolantOverrideLink link_{cnc_};
  std::unique_ptr<runtime::Compensator> comp_;
  std::shared_ptr<const model::CompositeModel> model_;
  std::unique_ptr<store::HistoryWriter> writer_;
  std::unique_ptr<station::HistoryLogger> logger_;
  std::unique_ptr<RunBackend> backend_;
  double unix0_ = 0, t_ = 0;
  long cycle_ = 0;
};

TEST_F(RunBackendTest, ShowsTheRunningMachineAndItsLiveValues) {
  temps_.Set("nut", 26);
  const runtime::CycleRecord rec = Cycles(300);
  const auto list = backend_->ListMachines();
  ASSERT_EQ(list.size(), 1u);
  const MachineSummary& m = list[0];
  EXPECT_EQ(m.id, "vmc1");
  EXPECT_TRUE(m.connected);
  ASSERT_EQ(m.axes.size(), 1u);
  EXPECT_DOUBLE_EQ(m.axes[0].correction_um, rec.axes[0].output_um);
  EXPECT_NE(m.axes[0].correction_um, 0.0) << "a warm nut gives a correction";
  EXPECT_DOUBLE_EQ(m.axes[0].target_um, rec.axes[0].desired_um);
  ASSERT_EQ(m.channels.size(), 2u);
  EXPECT_NEAR(m.channels[0].temp_c, 26, 0.5);
  EXPECT_EQ(m.model.revision, std::to_string(model_->revision));
  const LiveSeries live = backend_->Live("vmc1", 0, 1000);
  EXPECT_EQ(live.samples.size(), 30u);
  EXPECT_EQ(live.last_sequence, 30u);
  EXPECT_EQ(backend_->Live("vmc1", 25, 1000).samples.size(), 5u);
  EXPECT_THROW(backend_->Live("other", 0, 10), BackendError);
}

TEST_F(RunBackendTest, AxisDisableRampsTheCorrectionThroughTheLimiter) {
  temps_.Set("nut", 30);
  const double before = Cycles(400).axes[0].output_um;
  ASSERT_GT(std::abs(before), 2.0);
  backend_->SetAxisEnabled(kWho, "vmc1", "X", false);
  const double next = Cycles(10).axes[0].output_um;
  EXPECT_GT(std::abs(next), 0.0) << "no jump to zero: it ramps";
  EXPECT_LT(std::abs(next), std::abs(before));
  EXPECT_NEAR(Cycles(2000).axes[0].output_um, 0.0, 1e-9);
  EXPECT_FALSE(backend_->ListMachines()[0].axes[0].enabled);
  EXPECT_THROW(backend_->SetAxisEnabled(kWho, "vmc1", "Q", false), BackendError);
}

TEST_F(RunBackendTest, CoolantOverrideReachesTheCompensator) {
  Cycles(20);
  EXPECT_EQ(backend_->ListMachines()[0].coolant, "off");
  backend_->SetCoolantOverride(kWho, "vmc1", "flood");
  Cycles(20);
  EXPECT_EQ(backend_->ListMachines()[0].coolant, "flood");
  EXPECT_EQ(backend_->Machine("vmc1").summary.coolant_override, "flood");
  EXPECT_THROW(backend_->SetCoolantOverride(kWho, "vmc1", "steam"), BackendError);
  backend_->SetCoolantOverride(kWho, "vmc1", "");
  Cycles(20);
  EXPECT_EQ(backend_->ListMachines()[0].coolant, "off");
}

TEST_F(RunBackendTest, LoadsAndRollsBackModelRevisions) {
  auto second = std::make_shared<model::CompositeModel>(*model_);
  second->revision = model_->revision + 1;
  comp_->PublishModel(second, "second");
  backend_->OnModelPublished({std::to_string(second->revision), second, {}}, "bb", "reloaded", unix0_ + 1);
  EXPECT_EQ(backend_->Machine("vmc1").summary.model.revision, std::to_string(second->revision));
  EXPECT_EQ(backend_->RollbackModel(kWho, "vmc1"), std::to_string(model_->revision));
  EXPECT_EQ(backend_->Machine("vmc1").summary.model.revision, std::to_string(model_->revision));
  EXPECT_THROW(backend_->RollbackModel(kWho, "vmc1"), BackendError) << "nothing earlier";
  backend_->LoadModelRevision(kWho, "vmc1", std::to_string(second->revision));
  EXPECT_EQ(backend_->Machine("vmc1").summary.model.revision, std::to_string(second->revision));
  EXPECT_EQ(backend_->Machine("vmc1").model.available.size(), 2u);
  EXPECT_THROW(backend_->LoadModelRevision(kWho, "vmc1", "77"), BackendError);
}

// A per-axis model as a deployed thermal model is (station::PublishedModel without a composite):
// a constant error, so the compensator's target tells which model runs.
class ConstantAxisModel final : public model::AxisErrorModel {
 public:
  explicit ConstantAxisModel(double error_um) : error_um_(error_um) {}
  const std::string& Axis() const override { return axis_; }
  const std::vector<std::string>& Sensors() const override { return sensors_; }
  std::string Describe() const override { return "constant"; }
  double ErrorUm(double, Direction, std::span<const double>, CoolantState, const model::AxisModelDynamics&) const override {
    return error_um_;
  }

 private:
  double error_um_;
  std::string axis_ = "X";
  std::vector<std::string> sensors_ = {"nut"};
};

TEST_F(RunBackendTest, AThermalModelIsListedAndCanBeRolledBackAndLoadedAgain) {
  const station::PublishedModel thermal{"ridge", nullptr, {std::make_shared<const ConstantAxisModel>(7.0)}};
  station::PublishTo(*comp_, thermal, "thermal.json");
  backend_->OnModelPublished(thermal, "cc0123456789", "thermal.json", unix0_ + 1);
  const auto target = [&] {
    double desired = 0;
    for (int i = 0; i < 5; ++i) desired = comp_->RunCycle(link_, temps_, t_ += 0.01).axes[0].desired_um;
    return desired;
  };
  EXPECT_NEAR(target(), -7.0, 1e-9);  // correction = −error
  MachineDetail d = backend_->Machine("vmc1");
  EXPECT_EQ(d.summary.model.revision, "ridge-cc012345");  // its kind, told apart by the file's hash
  EXPECT_EQ(d.model.available.size(), 2u);
  EXPECT_EQ(backend_->RollbackModel(kWho, "vmc1"), std::to_string(model_->revision));
  EXPECT_GT(std::fabs(target() + 7.0), 0.1) << "the seed-000 model runs again";
  backend_->LoadModelRevision(kWho, "vmc1", "ridge-cc012345");
  EXPECT_NEAR(target(), -7.0, 1e-9);
}

TEST_F(RunBackendTest, HistoryExportAndAlarmsComeFromTheRun) {
  temps_.Set("nut", 24);
  Cycles(500);
  temps_.SetFault("nut", true);
  Cycles(300);
  const double now = unix0_ + t_;
  const HistorySeries h = backend_->History("vmc1", unix0_ - 1, now + 1, 10);
  ASSERT_EQ(h.temperatures.size(), 2u);
  ASSERT_EQ(h.corrections.size(), 1u);
  EXPECT_LE(h.temperatures[0].points.size(), 10u);
  EXPECT_TRUE(h.decimated);
  const ExportFile csv = backend_->Export("vmc1", unix0_ - 1, now + 1, ExportFormat::kCsvCompensation);
  EXPECT_EQ(csv.bytes.rfind("time_s,", 0), 0u) << csv.bytes.substr(0, 60);
  EXPECT_GT(std::count(csv.bytes.begin(), csv.bytes.end(), '\n'), 50);
  const ExportFile xlsx = backend_->Export("vmc1", unix0_ - 1, now + 1, ExportFormat::kXlsx);
  EXPECT_EQ(xlsx.bytes.substr(0, 2), "PK");
  const auto alarms = backend_->Alarms(10);
  ASSERT_FALSE(alarms.empty()) << "the faulty nut sensor raises an alarm";
  EXPECT_TRUE(alarms[0].active);
  EXPECT_NE(alarms[0].name.find("sensor_"), std::string::npos) << alarms[0].name;
  EXPECT_NE(alarms[0].name.find("(X)"), std::string::npos) << "the page names the axis: " << alarms[0].name;
  backend_->AcknowledgeAlarm(kWho, alarms[0].id);
  EXPECT_EQ(backend_->Alarms(10)[0].acknowledged_by, "op");
}

TEST(RunBackendOptions, RefusesAnIdTheUrlCannotCarry) {
  trueaxis::testing::MockCnc cnc{{"X"}};
  trueaxis::testing::MockTemperatures temps{{"nut"}, 20.0};
  auto comp = runtime::Compensator::ForHardware(runtime::CompensatorOptions{}, cnc, temps, {});
  RunBackendOptions o;
  o.machine_id = "bad/id";
  EXPECT_ANY_THROW(RunBackend(*comp, nullptr, nullptr, o));
}

}  // namespace
}  // namespace trueaxis::web
