// The workshop server's machines on the web front end (web::ShopBackend over server::Shop): a
// virtual shop of three machines on 127.0.0.1, polled by a real Shop, seen and operated through
// the MonitorBackend the pages use.
#include "trueaxis/web/shop_backend.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "../server/shop_fixture.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/store/history_writer.hpp"
#include "trueaxis/web/model_figures.hpp"

namespace trueaxis::web {
namespace {

using server::testing::ConfigFor;
using server::testing::StartVirtualShop;
using server::testing::TempDir;
using server::testing::WaitFor;
using server::testing::WriteModel;

class ShopBackendTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = TempDir("web_shop_backend");
    model_ = WriteModel(dir_ + "/model_a.json", 1.0);
    model_b_ = WriteModel(dir_ + "/model_b.json", 2.0);
    vshop_ = StartVirtualShop(3);
    ASSERT_TRUE(vshop_);
    config_ = ConfigFor(*vshop_, model_);
    history_db_ = dir_ + "/history.sqlite";
    writer_ = std::make_unique<store::HistoryWriter>(history_db_);
    shop_ = std::make_unique<server::Shop>(config_, writer_.get());
    shop_->Start();
    ShopBackendOptions o;
    o.history_db = history_db_;
    o.sample_period_s = 0.05;
    backend_ = std::make_unique<ShopBackend>(*shop_, writer_.get(), o);
    backend_->Start();
    ASSERT_TRUE(WaitFor([&] {
      for (const auto& m : backend_->ListMachines())
        if (!m.connected) return false;
      return true;
    }));
  }
  void TearDown() override {
    if (backend_) backend_->Stop();
    if (shop_) shop_->Stop();
    if (vshop_) vshop_->Stop();
  }
  std::string Name(std::size_t i) const { return config_.machines[i].name; }

  std::string dir_, model_, model_b_, history_db_;
  std::unique_ptr<sim::VirtualShop> vshop_;
  server::ShopConfig config_;
  std::unique_ptr<store::HistoryWriter> writer_;
  std::unique_ptr<server::Shop> shop_;
  std::unique_ptr<ShopBackend> backend_;
  const Actor anna_{"anna", "127.0.0.1"};
};

TEST_F(ShopBackendTest, ListsEveryMachineWithItsValuesAndLiveSamples) {
  const auto list = backend_->ListMachines();
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(backend_->Describe(), "shop: 3 machines");
  for (std::size_t i = 0; i < list.size(); ++i) {
    EXPECT_EQ(list[i].id, Name(i));
    EXPECT_EQ(list[i].axes.size(), config_.machines[i].axes.size());
    EXPECT_EQ(list[i].channels.size(), config_.machines[i].channels.size());
    EXPECT_EQ(list[i].model.revision, "1");
  }
  // temperatures arrive (read once per second by the shop)
  ASSERT_TRUE(WaitFor([&] {
    const auto m = backend_->Machine(Name(1)).summary;
    return !m.channels.empty() && std::isfinite(m.channels[0].temp_c) && m.channels[0].temp_c > 5 && m.channels[0].temp_c < 60;
  }));
  const LiveSeries first = backend_->Live(Name(1), 0, 1000);
  EXPECT_EQ(first.axes, config_.machines[1].axes);
  EXPECT_EQ(first.channels, config_.machines[1].channels);
  ASSERT_TRUE(WaitFor([&] { return backend_->Live(Name(1), first.last_sequence, 1000).samples.size() >= 2; }));
  const LiveSeries next = backend_->Live(Name(1), first.last_sequence, 1000);
  for (const auto& s : next.samples) {
    EXPECT_GT(s.sequence, first.last_sequence);
    EXPECT_EQ(s.correction_um.size(), config_.machines[1].axes.size());
  }
  EXPECT_THROW(backend_->Machine("no-such-machine"), BackendError);
  EXPECT_THROW(backend_->Live("no-such-machine", 0, 10), BackendError);
}

TEST_F(ShopBackendTest, ALostTerminalIsShownUnavailableNeverAsItsLastNumbers) {
  ASSERT_TRUE(WaitFor([&] { return std::isfinite(backend_->Machine(Name(2)).summary.axes[0].position_mm); }));
  vshop_->SetFault(2, sim::TerminalFault::kDown);
  ASSERT_TRUE(WaitFor([&] { return !backend_->Machine(Name(2)).summary.connected; }));
  const auto m = backend_->Machine(Name(2)).summary;
  for (const auto& a : m.axes) EXPECT_TRUE(std::isnan(a.position_mm)) << a.name;
  for (const auto& c : m.channels) EXPECT_TRUE(std::isnan(c.temp_c)) << c.name;
  EXPECT_FALSE(m.alarms.empty());
  // the alarm reaches the alarm list, and acknowledging it acknowledges it on the shop
  ASSERT_TRUE(WaitFor([&] {
    for (const auto& e : backend_->Alarms(100))
      if (e.machine_id == Name(2) && e.active) return true;
    return false;
  }));
  std::string id;
  for (const auto& e : backend_->Alarms(100))
    if (e.machine_id == Name(2) && e.active) id = e.id;
  // the other machines go on meanwhile
  EXPECT_TRUE(backend_->Machine(Name(0)).summary.connected);
  // the terminal comes back; the shop keeps the alarm raised until someone acknowledges it
  vshop_->SetFault(2, sim::TerminalFault::kNone);
  ASSERT_TRUE(WaitFor([&] {
    const auto m2 = shop_->Machine(Name(2));
    return m2->connected && m2->alarms == 0;
  }));
  EXPECT_NE(shop_->Machine(Name(2))->unacknowledged, 0u);
  backend_->AcknowledgeAlarm(anna_, id);
  EXPECT_EQ(shop_->Machine(Name(2))->unacknowledged, 0u);
  EXPECT_THROW(backend_->AcknowledgeAlarm(anna_, id), BackendError);  // once
}

TEST_F(ShopBackendTest, OperationsReachTheShopAndBadOnesAreRefused) {
  backend_->SetAxisEnabled(anna_, Name(0), config_.machines[0].axes[0], false);
  EXPECT_FALSE(shop_->Machine(Name(0))->axes[0].enabled);
  EXPECT_FALSE(backend_->Machine(Name(0)).summary.axes[0].enabled);
  try {
    backend_->SetAxisEnabled(anna_, Name(0), "Q", false);
    FAIL() << "no axis Q";
  } catch (const BackendError& e) {
    EXPECT_EQ(e.status(), 404);
  }
  backend_->SetCoolantOverride(anna_, Name(1), "flood");
  EXPECT_EQ(backend_->Machine(Name(1)).summary.coolant_override, "flood");
  backend_->SetCoolantOverride(anna_, Name(1), "");
  EXPECT_EQ(backend_->Machine(Name(1)).summary.coolant_override, "");
  try {
    backend_->SetCoolantOverride(anna_, Name(1), "lava");
    FAIL() << "lava is no coolant";
  } catch (const BackendError& e) {
    EXPECT_EQ(e.status(), 400);
  }
}

TEST_F(ShopBackendTest, ModelRevisionsAreTheFilesTheMachineRanWithWhoAndFromWhere) {
  MachineDetail d = backend_->Machine(Name(0));
  ASSERT_EQ(d.model.available.size(), 1u);
  EXPECT_EQ(d.summary.model.file, model_);
  EXPECT_EQ(d.model.figures.size(), FiguresFromFitSummary(model::ReadModelFile(model_)).size());  // the file's fit summary
  EXPECT_EQ(d.model.label.find("not shown"), std::string::npos) << d.model.label;
  // nothing to roll back to, and a file the machine never ran cannot be loaded from the page
  EXPECT_THROW(backend_->RollbackModel(anna_, Name(0)), BackendError);
  EXPECT_THROW(backend_->LoadModelRevision(anna_, Name(0), model_b_), BackendError);
  // loaded from the server's CLI, then back and forth from the page
  shop_->LoadModel(Name(0), model_b_, "bob", "cli");
  ASSERT_TRUE(WaitFor([&] { return backend_->Machine(Name(0)).summary.model.file == model_b_; }));
  d = backend_->Machine(Name(0));
  EXPECT_EQ(d.summary.model.file, model_b_);
  EXPECT_EQ(d.summary.model.revision, "2");
  ASSERT_EQ(d.model.available.size(), 2u);
  EXPECT_EQ(backend_->RollbackModel(anna_, Name(0)), model_);
  ASSERT_TRUE(WaitFor([&] { return backend_->Machine(Name(0)).summary.model.file == model_; }));
  backend_->LoadModelRevision(anna_, Name(0), model_b_);
  const auto changes = shop_->ModelChanges(Name(0));
  ASSERT_EQ(changes.size(), 3u);
  EXPECT_EQ(changes[1].user, "anna");
  EXPECT_EQ(changes[1].from, "127.0.0.1");
  EXPECT_EQ(changes[1].action, "rollback");
  EXPECT_EQ(changes[2].new_model.file, model_b_);
  EXPECT_TRUE(WaitFor([&] { return backend_->Machine(Name(0)).summary.model.file == model_b_; }));
}

TEST_F(ShopBackendTest, AModelFileRewrittenSinceItWasLoadedShowsNoFiguresAndSaysWhy) {
  WriteModel(model_, 3.0);  // the file on disk is now another model; the machines run the loaded one
  const MachineDetail d = backend_->Machine(Name(1));
  EXPECT_TRUE(d.model.figures.empty());
  EXPECT_NE(d.model.label.find("has changed since it was loaded"), std::string::npos) << d.model.label;
}

TEST_F(ShopBackendTest, HistoryAndExportShowOneMachineUnderItsOwnNames) {
  ASSERT_TRUE(WaitFor([&] {
    const auto h = backend_->History(Name(1), 0, 4e9, 100);
    return !h.corrections.empty() && !h.temperatures.empty();
  }));
  const HistorySeries h = backend_->History(Name(1), 0, 4e9, 100);
  ASSERT_EQ(h.corrections.size(), config_.machines[1].axes.size());
  for (std::size_t i = 0; i < h.corrections.size(); ++i) EXPECT_EQ(h.corrections[i].name.find('/'), std::string::npos);
  for (const auto& t : h.temperatures) {
    EXPECT_EQ(t.name.find('/'), std::string::npos);
    EXPECT_LE(t.points.size(), 100u);
  }
  const ExportFile csv = backend_->Export(Name(1), 0, 4e9, ExportFormat::kCsvCompensation);
  EXPECT_EQ(csv.file_name, Name(1) + "_compensation.csv");
  EXPECT_NE(csv.bytes.find(Name(1) + "/"), std::string::npos);   // its rows
  EXPECT_EQ(csv.bytes.find(Name(0) + "/"), std::string::npos);   // and no other machine's
  EXPECT_EQ(csv.bytes.find(Name(2) + "/"), std::string::npos);
}

}  // namespace
}  // namespace trueaxis::web
