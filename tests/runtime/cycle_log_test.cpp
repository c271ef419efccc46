// The installation's record (station::CycleLog, opened by Installation::OpenLog): the history
// database, the CSV log and the watchers (the web page) get every recorded cycle and every model
// the installation publishes — the one way `run` and the demo write their history.
#include "trueaxis/station/cycle_log.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fakes.hpp"
#include "trueaxis/core/text_file.hpp"
#include "trueaxis/model/model_json.hpp"
#include "trueaxis/model/sha256.hpp"
#include "trueaxis/runtime/loop_runner.hpp"
#include "trueaxis/station/installation.hpp"
#include "trueaxis/store/history_db.hpp"

namespace trueaxis::station {
namespace {
namespace fs = std::filesystem;
using runtime::testing::MockCnc;
using runtime::testing::MockTemperatures;
using runtime::testing::TestModel;

// One axis X moving at 400 mm, three channels, a model file; the installation as `run` makes it.
struct Rig {
  explicit Rig(const std::string& name)
      : dir(fs::temp_directory_path() / ("trueaxis_cycle_log_" + name + "_" + std::to_string(getpid()))),
        cnc({"X"}),
        temps({"ambient", "nut", "bearing"}, 24.0) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    config.source = (dir / "run.toml").string();
    config.model_file = (dir / "model.json").string();
    config.period_s = 0.01;
    config.temperature_period_s = 0.01;
    config.compensator.shaper.max_step_um = 1000;
    config.axes = {runtime::AxisInterface{"X"}};
    model::WriteModelFile(*TestModel(1.0, {"X"}), config.model_file);
    cnc.axes[0] = {400, +1, true};
  }
  ~Rig() { fs::remove_all(dir); }
  HistoryConfig History(const std::string& stem) const {
    HistoryConfig h;
    h.db = (dir / (stem + ".sqlite")).string();
    h.csv = (dir / (stem + ".csv")).string();
    h.record_interval_s = 0.1;
    return h;
  }
  fs::path dir;
  MockCnc cnc;
  MockTemperatures temps;
  InstallationConfig config;
  double now = 0;
};

// `run`: the loop records into the log's ring, the owner drains it.
std::vector<runtime::CycleRecord> RunCycles(Rig& rig, Installation& installation, std::uint64_t cycles) {
  runtime::LoopRunner runner(installation.compensator(), rig.cnc, installation.temperatures(),
                             runtime::LoopOptions{rig.config.period_s, rig.config.temperature_period_s},
                             &installation.log()->recorder());
  runner.StepSimulated(cycles, [&](double dt) { rig.now += dt; });
  std::vector<runtime::CycleRecord> seen;
  installation.log()->Drain([&](const runtime::CycleRecord& r) { seen.push_back(r); });
  return seen;
}

TEST(CycleLog, RunsCyclesAndItsModelGoToTheHistoryAndTheCsvLog) {
  Rig rig("run");
  Installation installation(rig.config, rig.cnc, rig.temps, [&] { return rig.now; }, "");
  const HistoryConfig h = rig.History("run");
  CycleLog& log = installation.OpenLog(h, 1000.0);
  const auto seen = RunCycles(rig, installation, 200);  // 2 s at 10 ms, a record every 0.1 s
  ASSERT_GE(seen.size(), 20u);
  EXPECT_LE(seen.size(), 30u);  // decimated: every 10th cycle and the alarm changes only
  log.Close();

  store::HistoryDb db(h.db, store::HistoryDb::Mode::kReadOnly);
  const auto compensation = db.QueryCompensation({});
  ASSERT_EQ(compensation.size(), seen.size());
  for (std::size_t i = 0; i < seen.size(); ++i) {
    EXPECT_NEAR(compensation[i].time_s, 1000.0 + seen[i].time_s, 1e-6);  // the loop's time on the Unix clock
    EXPECT_NEAR(compensation[i].correction_um, seen[i].axes[0].output_um, 1e-9);
  }
  EXPECT_NE(seen.back().axes[0].output_um, 0.0) << "the model compensates: the rows carry a correction";
  EXPECT_EQ(db.QueryTemperatures({}).size(), 3 * seen.size());
  const auto models = db.QueryModelChanges({});
  ASSERT_EQ(models.size(), 1u);
  EXPECT_EQ(models[0].note, "loaded " + rig.config.model_file);
  EXPECT_EQ(models[0].sha256, model::Sha256OfFile(rig.config.model_file));
  EXPECT_EQ(models[0].revision, installation.model().revision);
  EXPECT_DOUBLE_EQ(models[0].time_s, 1000.0);

  const std::string csv = ReadTextFile(h.csv);
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "time_s,alarms,X_position_mm,X_correction_um,t_ambient_c,t_nut_c,t_bearing_c");
  EXPECT_EQ(static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n')), seen.size() + 1);
}

// The demo hands its sampled records to the log directly: the rows are the ones `run` writes for
// the same records.
TEST(CycleLog, TheDemosRecordsAreWrittenAsRunsAre) {
  Rig rig("demo");
  Installation run(rig.config, rig.cnc, rig.temps, [&] { return rig.now; }, "");
  const HistoryConfig run_history = rig.History("run");
  run.OpenLog(run_history, 1000.0);
  const auto seen = RunCycles(rig, run, 100);
  run.log()->Close();

  Installation demo(rig.config, rig.cnc, rig.temps, [&] { return rig.now; }, "");
  const HistoryConfig demo_history = rig.History("demo");
  CycleLog& log = demo.OpenLog(demo_history, 1000.0);
  for (const auto& r : seen) log.Log(r);
  log.Close();

  store::HistoryDb a(run_history.db, store::HistoryDb::Mode::kReadOnly);
  store::HistoryDb b(demo_history.db, store::HistoryDb::Mode::kReadOnly);
  const auto ca = a.QueryCompensation({}), cb = b.QueryCompensation({});
  ASSERT_EQ(ca.size(), cb.size());
  ASSERT_FALSE(ca.empty());
  for (std::size_t i = 0; i < ca.size(); ++i) {
    EXPECT_EQ(ca[i].time_s, cb[i].time_s);
    EXPECT_EQ(ca[i].correction_um, cb[i].correction_um);
    EXPECT_EQ(ca[i].state, cb[i].state);
  }
  const auto ta = a.QueryTemperatures({}), tb = b.QueryTemperatures({});
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) EXPECT_EQ(ta[i].filtered_c, tb[i].filtered_c);
  EXPECT_EQ(ReadTextFile(run_history.csv), ReadTextFile(demo_history.csv));
}

// A watcher (the web page) is told the model in force when it starts watching, each drained
// record, and a model the installation reloads; the history records the reload too.
TEST(CycleLog, AWatcherSeesTheModelInForceRecordsAndAReload) {
  Rig rig("watch");
  rig.config.model_reload = true;
  Installation installation(rig.config, rig.cnc, rig.temps, [&] { return rig.now; }, "");
  const HistoryConfig h = rig.History("watch");
  CycleLog& log = installation.OpenLog(h, 1000.0);
  std::vector<std::string> labels;
  std::vector<double> model_times;
  std::size_t records = 0;
  log.Watch({[&](const runtime::CycleRecord&) { ++records; },
             [&](const PublishedModel&, const std::string&, const std::string& label, double unix_s) {
               labels.push_back(label);
               model_times.push_back(unix_s);
             }});
  ASSERT_EQ(labels.size(), 1u);
  EXPECT_EQ(labels[0], rig.config.model_file);
  EXPECT_DOUBLE_EQ(model_times[0], 1000.0);
  const auto seen = RunCycles(rig, installation, 50);
  EXPECT_EQ(records, seen.size());

  EXPECT_FALSE(installation.ReloadIfChanged()) << "unchanged file";
  model::WriteModelFile(*TestModel(2.0, {"X"}), rig.config.model_file);
  fs::last_write_time(rig.config.model_file, fs::last_write_time(rig.config.model_file) + std::chrono::seconds(2));
  ASSERT_TRUE(installation.ReloadIfChanged());
  ASSERT_EQ(labels.size(), 2u);
  EXPECT_EQ(labels[1], "reloaded " + rig.config.model_file);
  EXPECT_GT(model_times[1], 1000.0);
  log.Close();
  store::HistoryDb db(h.db, store::HistoryDb::Mode::kReadOnly);
  const auto models = db.QueryModelChanges({});
  ASSERT_EQ(models.size(), 2u);
  EXPECT_EQ(models[1].note, "reloaded " + rig.config.model_file);
  EXPECT_EQ(models[1].sha256, model::Sha256OfFile(rig.config.model_file));
  EXPECT_NE(models[1].sha256, models[0].sha256);
}

// No [history]: nothing is opened, the loop's records are still handed to the watchers.
TEST(CycleLog, WithoutAHistoryNothingIsWritten) {
  Rig rig("none");
  Installation installation(rig.config, rig.cnc, rig.temps, [&] { return rig.now; }, "");
  CycleLog& log = installation.OpenLog(HistoryConfig{}, 0);
  EXPECT_EQ(log.writer(), nullptr);
  std::size_t records = 0;
  log.Watch({[&](const runtime::CycleRecord&) { ++records; }, nullptr});
  const auto seen = RunCycles(rig, installation, 30);
  EXPECT_EQ(records, seen.size());
  EXPECT_GT(records, 0u);
  log.Close();
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(rig.dir)) ++files;
  EXPECT_EQ(files, 1u) << "only the model file";
}

}  // namespace
}  // namespace trueaxis::station
