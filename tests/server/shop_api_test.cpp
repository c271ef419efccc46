// Models change on the server only: load / replace / roll back while the shop
// runs, recorded with who, when, old and new revision; the HTTP API and the CLI
// in front of it; independent MODBUS peers (mbpoll, pymodbus) reading a
// virtual-shop terminal; the history surviving kill -9 of the server.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "shop_fixture.hpp"
#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/http_api.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/store/history_db.hpp"
#include "trueaxis/store/history_writer.hpp"

namespace trueaxis::server {
namespace {

using namespace trueaxis::server::testing;

std::string RunShell(const std::string& cmd, int* status) {
  std::string out;
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  *status = pclose(p);
  return out;
}

TEST(ShopModels, LoadRollbackAreRampedRecordedAndABadModelKeepsTheRunningOne) {
  const std::string dir = TempDir("models");
  const std::string m1 = WriteModel(dir + "/m1.json", 1.0);
  const std::string m2 = WriteModel(dir + "/m2.json", 2.0);  // twice the correction, revision 2
  const std::string bad = WriteModel(dir + "/bad.json", 1.0, "_no_such_sensor");
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  ShopConfig config = ConfigFor(*vshop, m1);
  config.audit_log = dir + "/audit.jsonl";
  config.history = dir + "/shop.db";
  for (auto& m : config.machines) m.installation.compensator.shaper.max_step_um = 5;  // ramps of a few cycles keep the test short
  const double step_um = config.machines[0].installation.compensator.shaper.max_step_um;
  auto writer = std::make_unique<store::HistoryWriter>(config.history);
  Shop shop(config, writer.get());
  shop.Start();
  // Settle on model 1.
  ASSERT_TRUE(WaitFor([&] { return std::abs(vshop->AppliedUm(0)[0]) > 20 && shop.Machine("vm-0000")->complete_cycles > 10; }));
  ASSERT_TRUE(WaitFor([&] {
    const auto s = *shop.Machine("vm-0000");
    return std::abs(s.axes[0].output_um + s.axes[0].target_um) < 1e9 && std::abs(s.axes[0].output_um - s.axes[0].target_um) < 2;
  }));
  EXPECT_THROW(shop.LoadModel("vm-0000", bad, "alice", "test"), InputError);
  EXPECT_THROW(shop.LoadModel("no-such-machine", m2, "alice", "test"), InputError);
  EXPECT_THROW(shop.Rollback("vm-0000", "alice", "test"), InputError);  // nothing before the first model
  const ModelChange c = shop.LoadModel("vm-0000", m2, "alice", "10.0.0.7");
  EXPECT_EQ(c.old_model.revision, 1);
  EXPECT_EQ(c.new_model.revision, 2);
  EXPECT_EQ(c.user, "alice");
  // The switch ramps: the CNC never sees more than one limiter step per write.
  auto last = vshop->AppliedUm(0);
  double worst = 0;
  bool reached = false;
  for (int i = 0; i < 2000 && !reached; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const auto now = vshop->AppliedUm(0);
    worst = std::max(worst, std::abs(now[0] - last[0]));
    last = now;
    const auto s = *shop.Machine("vm-0000");
    reached = s.model.revision == 2 && std::abs(s.axes[0].output_um - s.axes[0].target_um) < 2;
  }
  EXPECT_TRUE(reached);
  EXPECT_LE(worst, std::max(step_um, 1.0) + 1e-9);
  EXPECT_EQ(shop.Machine("vm-0001")->model.revision, 1);  // the other machine keeps its model
  const ModelChange r = shop.Rollback("vm-0000", "bob", "cli");
  EXPECT_EQ(r.old_model.revision, 2);
  EXPECT_EQ(r.new_model.revision, 1);
  ASSERT_TRUE(WaitFor([&] { return shop.Machine("vm-0000")->model.revision == 1; }));
  shop.Stop();
  writer->Close();

  EXPECT_EQ(shop.ModelChanges("vm-0000").size(), 2u);
  std::ifstream audit(config.audit_log);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(audit, line);) lines.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0]["user"], "alice");
  EXPECT_EQ(lines[0]["from"], "10.0.0.7");
  EXPECT_EQ(lines[0]["old_revision"], 1);
  EXPECT_EQ(lines[0]["new_revision"], 2);
  EXPECT_EQ(lines[1]["action"], "rollback");
  store::HistoryDb db(config.history, store::HistoryDb::Mode::kReadOnly);
  const auto changes = db.QueryModelChanges({});
  ASSERT_EQ(changes.size(), 4u);  // two starts, the load, the rollback
  EXPECT_NE(changes[2].note.find("vm-0000 load by alice"), std::string::npos) << changes[2].note;
  // Every machine's corrections are in the shared history under "machine/axis".
  EXPECT_FALSE(db.QueryCompensation({}, {"vm-0000/X"}).empty());
  EXPECT_FALSE(db.QueryCompensation({}, {"vm-0001/Z"}).empty());
  EXPECT_FALSE(db.QueryTemperatures({}, {"vm-0001/ambient"}).empty());
}

TEST(ShopHttpApi, StatusModelsAndErrorsOverHttpAndTheCli) {
  const std::string dir = TempDir("http");
  const std::string m1 = WriteModel(dir + "/m1.json", 1.0);
  const std::string m2 = WriteModel(dir + "/m2.json", 2.0);
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  vshop->SetFault(1, TerminalFault::kDown);
  Shop shop(ConfigFor(*vshop, m1), nullptr);
  HttpApi api(shop, "127.0.0.1", 0);
  std::string error;
  ASSERT_TRUE(api.Start(&error)) << error;
  shop.Start();
  ASSERT_TRUE(WaitFor([&] { return shop.Machine("vm-0000")->complete_cycles > 3 && shop.Machine("vm-0001")->faults > 0; }));
  httplib::Client client("127.0.0.1", api.port());
  auto res = client.Get("/api/machines");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  const auto all = nlohmann::json::parse(res->body);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_TRUE(all[0]["connected"].get<bool>());
  EXPECT_TRUE(all[0]["axes"][0]["position_mm"].is_number());
  EXPECT_FALSE(all[1]["connected"].get<bool>());
  EXPECT_TRUE(all[1]["axes"][0]["position_mm"].is_null());  // UNAVAILABLE
  EXPECT_EQ(all[1]["axes"][0]["state"], "link_lost");
  EXPECT_EQ(all[0]["axes"][0]["state"], "full");  // the model with its own x_nut and room sensor
  EXPECT_TRUE(all[1]["channels"][0]["temp_c"].is_null());
  EXPECT_NE(all[1]["last_fault"].get<std::string>().find("connect"), std::string::npos);

  EXPECT_EQ(client.Get("/api/machines/nope")->status, 404);
  EXPECT_EQ(client.Post("/api/machines/vm-0000/model", R"({"file": "/no/such.json", "user": "x"})", "application/json")->status, 422);
  EXPECT_EQ(client.Post("/api/machines/vm-0000/model", R"({"file": "/no/such.json"})", "application/json")->status, 400);
  EXPECT_EQ(client.Post("/api/machines/vm-0000/axes/Q", R"({"enabled": false, "user": "x"})", "application/json")->status, 404);
  res = client.Post("/api/machines/vm-0000/axes/Y", R"({"enabled": false, "user": "x"})", "application/json");
  ASSERT_EQ(res->status, 200);
  EXPECT_FALSE(nlohmann::json::parse(res->body)["axes"][1]["enabled"].get<bool>());
  res = client.Post("/api/machines/vm-0000/coolant", R"({"override": "flood", "user": "x"})", "application/json");
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(nlohmann::json::parse(res->body)["coolant_override"], "flood");

  // The CLI against the running server.
  const std::string url = "http://127.0.0.1:" + std::to_string(api.port());
  auto cli = trueaxis::testing::RunCli("server model load --url " + url + " --machine vm-0000 --file " + m2 + " --user carol");
  EXPECT_EQ(cli.exit_code, 0) << cli.output;
  EXPECT_EQ(nlohmann::json::parse(cli.output)["new"]["revision"], "2") << cli.output;
  cli = trueaxis::testing::RunCli("server model rollback --url " + url + " --machine vm-0001 --user carol");
  EXPECT_EQ(cli.exit_code, 2) << cli.output;  // nothing to roll back to
  cli = trueaxis::testing::RunCli("server status --url " + url);
  EXPECT_EQ(cli.exit_code, 0) << cli.output;
  EXPECT_NE(cli.output.find("vm-0001      DOWN"), std::string::npos) << cli.output;
  EXPECT_NE(cli.output.find("UNAVAILABLE"), std::string::npos) << cli.output;
  res = client.Get("/api/machines/vm-0000/models");
  ASSERT_EQ(res->status, 200);
  const auto changes = nlohmann::json::parse(res->body);
  ASSERT_EQ(changes.size(), 1u);
  EXPECT_EQ(changes[0]["user"], "carol");
  EXPECT_EQ(changes[0]["from"], "127.0.0.1");
  api.Stop();
  shop.Stop();
}

// mbpoll and pymodbus read a virtual-shop terminal as they would a real one.
TEST(VirtualShopPeers, MbpollAndPymodbusReadTheTerminal) {
  auto vshop = StartVirtualShop(3);
  ASSERT_NE(vshop, nullptr);
  const auto m = vshop->Machines()[2];
  int status = -1;
  std::string out = RunShell("mbpoll -m tcp -1 -o 2 -p " + std::to_string(m.port) + " -a 1 -t 3 -r 1 -c 8 127.0.0.1", &status);
  ASSERT_EQ(status, 0) << out;
  const std::regex line(R"(\[(\d+)\]:\s+(-?\d+))");
  std::map<int, long long> v;
  for (std::sregex_iterator it(out.begin(), out.end(), line), end; it != end; ++it) v[std::stoi((*it)[1])] = std::stoll((*it)[2]);
  EXPECT_EQ(v[1], 1) << out;  // layout
  EXPECT_EQ(v[2], 3) << out;  // axes
  EXPECT_EQ(v[6] & 0x2, 0x2) << out;  // CNC read OK
  out = RunShell(std::string("/usr/bin/python3 ") + TRUEAXIS_SOURCE_DIR + "/tests/drivers/peers/pymodbus_peer.py " +
                std::to_string(m.port) + " 3 -12.3 4.0 0",
            &status);
  ASSERT_EQ(status, 0) << out;
  const auto j = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(j["layout"], 1);
  EXPECT_EQ(j["axis_count"], 3);
  EXPECT_TRUE(j["write_ok"].get<bool>());
  EXPECT_EQ(j["adam_name"], 0x6015);
  for (int raw : j["adam_raw"]) {  // a VMC-850 in a room: every channel between 5 and 60 °C on the −50…150 °C range
    const double c = -50 + 200.0 * raw / 65535.0;
    EXPECT_GT(c, 5);
    EXPECT_LT(c, 60);
  }
  const auto applied = vshop->AppliedUm(2);
  EXPECT_NEAR(applied[0], -12.3, 1e-9);
  EXPECT_NEAR(applied[1], 4.0, 1e-9);
}

// kill -9 of the server: the history that was committed stays readable and holds every machine.
TEST(ShopHistory, SurvivesKillMinus9OfTheServer) {
  const std::string dir = TempDir("kill9");
  const std::string model = WriteModel(dir + "/model.json");
  auto vshop = StartVirtualShop(4);
  ASSERT_NE(vshop, nullptr);
  {
    std::ofstream f(dir + "/shop.toml");
    f << ShopFileFor(vshop->Machines(), "127.0.0.1", model, "shop.db", 0.05, 0) << "record_interval_s = 0.1\n";
  }
  // record_interval_s must be a root key: rewrite it at the top.
  {
    std::ifstream in(dir + "/shop.toml");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    text = "record_interval_s = 0.1\n" + text.substr(0, text.rfind("record_interval_s"));
    std::ofstream(dir + "/shop.toml") << text;
  }
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    freopen("/dev/null", "w", stdout);
    execl(TRUEAXIS_CLI_PATH, TRUEAXIS_CLI_PATH, "server", "--config", (dir + "/shop.toml").c_str(), "--quiet", nullptr);
    _exit(127);
  }
  ASSERT_TRUE(WaitFor([&] { return vshop->Stats().compensation_writes > 40; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status));
  store::HistoryDb db(dir + "/shop.db", store::HistoryDb::Mode::kReadOnly);
  for (const auto& m : vshop->Machines()) {
    EXPECT_GE(db.QueryCompensation({}, {m.name + "/X"}).size(), 2u) << m.name;
    EXPECT_GE(db.QueryTemperatures({}, {m.name + "/" + m.channels.back()}).size(), 2u) << m.name;
  }
  EXPECT_EQ(db.QueryModelChanges({}).size(), 4u);
}

}  // namespace
}  // namespace trueaxis::server
