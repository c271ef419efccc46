// The MTConnect agent over 127.0.0.1 against the virtual shop: in process (a terminal that stops
// makes only its own machine UNAVAILABLE; only changes are new observations; the Host check), and
// `trueaxis server --mtconnect` as its own process polled by an independent client (Python's
// urllib and xml.etree, tests/server/peers/mtconnect_client.py) that checks the documents against
// the structure the MTConnect 1.3 standard defines.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <regex>

#include <httplib.h>
#include <pugixml.hpp>

#include "shop_fixture.hpp"
#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/mtconnect_agent.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {
namespace {

using namespace trueaxis::server::testing;

struct Availability {
  std::map<std::string, std::string> by_device;
  std::uint64_t next = 0;
};

Availability CurrentAvailability(httplib::Client& client) {
  Availability a;
  auto res = client.Get("/current");
  if (!res || res->status != 200) return a;
  pugi::xml_document doc;
  if (!doc.load_string(res->body.c_str())) return a;
  a.next = doc.child("MTConnectStreams").child("Header").attribute("nextSequence").as_ullong();
  for (const auto& n : doc.select_nodes("//DeviceStream"))
    a.by_device[n.node().attribute("name").value()] = n.node().select_node(".//Availability").node().text().get();
  return a;
}

TEST(MtconnectAgent, AStoppedTerminalMakesOnlyItsOwnMachineUnavailable) {
  const std::string dir = TempDir("mtconnect_fault");
  auto vshop = StartVirtualShop(3);
  ASSERT_NE(vshop, nullptr);
  Shop shop(ConfigFor(*vshop, WriteModel(dir + "/model.json")), nullptr);
  MtconnectOptions o;
  o.port = 0;
  o.period_s = 0.05;
  MtconnectAgent agent(shop, o);
  std::string error;
  ASSERT_TRUE(agent.Start(&error)) << error;
  shop.Start();
  httplib::Client client("127.0.0.1", agent.port());
  ASSERT_TRUE(WaitFor([&] {
    const auto a = CurrentAvailability(client);
    return a.by_device.size() == 3 && a.by_device.at("vm-0000") == "AVAILABLE" && a.by_device.at("vm-0001") == "AVAILABLE" &&
           a.by_device.at("vm-0002") == "AVAILABLE";
  }));
  vshop->SetFault(1, TerminalFault::kDown);
  ASSERT_TRUE(WaitFor([&] { return CurrentAvailability(client).by_device["vm-0001"] == "UNAVAILABLE"; }));
  auto a = CurrentAvailability(client);
  EXPECT_EQ(a.by_device["vm-0000"], "AVAILABLE");
  EXPECT_EQ(a.by_device["vm-0002"], "AVAILABLE");
  // The fault is in the sample stream as one Availability change of that machine's own item.
  auto res = client.Get("/vm-0001/sample?path=//DataItem[@type=%22AVAILABILITY%22]&count=1000");
  ASSERT_TRUE(res);
  pugi::xml_document doc;
  ASSERT_TRUE(doc.load_string(res->body.c_str()));
  std::vector<std::string> history;
  for (const auto& n : doc.select_nodes("//Availability")) history.push_back(n.node().text().get());
  // UNAVAILABLE at the start, AVAILABLE once connected, UNAVAILABLE at the end; only changes are
  // observations, so no value follows itself (a link that flapped under load adds pairs, no repeats).
  ASSERT_GE(history.size(), 3u) << res->body.substr(0, 3000);
  EXPECT_EQ(history.front(), "UNAVAILABLE");
  EXPECT_EQ(history[1], "AVAILABLE");
  EXPECT_EQ(history.back(), "UNAVAILABLE");
  for (std::size_t i = 1; i < history.size(); ++i) EXPECT_NE(history[i], history[i - 1]) << i;
  vshop->SetFault(1, TerminalFault::kNone);  // back: AVAILABLE again once the server reconnects
  EXPECT_TRUE(WaitFor([&] { return CurrentAvailability(client).by_device["vm-0001"] == "AVAILABLE"; }));
  agent.Stop();
  shop.Stop();
}

TEST(MtconnectAgent, OnlyChangesAreNewObservationsAndOtherHostsAreRefused) {
  const std::string dir = TempDir("mtconnect_changes");
  auto vshop = StartVirtualShop(2);
  ASSERT_NE(vshop, nullptr);
  Shop shop(ConfigFor(*vshop, WriteModel(dir + "/model.json")), nullptr);  // not started: its values stand still
  MtconnectOptions o;
  o.port = 0;
  o.host_names = {"mtc.shop.example"};
  MtconnectAgent agent(shop, o);
  const auto next_of = [&] {
    pugi::xml_document doc;
    doc.load_string(agent.Respond("/current", {}).body.c_str());
    return doc.child("MTConnectStreams").child("Header").attribute("nextSequence").as_ullong();
  };
  const std::uint64_t initial = next_of();
  EXPECT_GT(initial, 2u * 10) << "every data item starts UNAVAILABLE, each one observation";
  agent.PublishOnce();
  const std::uint64_t after_first = next_of();
  agent.PublishOnce();
  agent.PublishOnce();
  EXPECT_EQ(next_of(), after_first) << "nothing changed: no new observation";
  EXPECT_GT(after_first, initial) << "the first look at the shop: its alarms and axis states";

  ASSERT_TRUE(agent.Start(nullptr));
  httplib::Client client("127.0.0.1", agent.port());
  auto res = client.Get("/probe", {{"Host", "attacker.example:5000"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 403);
  EXPECT_NE(res->body.find("UNAUTHORIZED"), std::string::npos);
  res = client.Get("/probe", {{"Host", "localhost:5000"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  res = client.Get("/probe", {{"Host", "MTC.shop.example:5000"}});  // a name given with --mtconnect-host-name
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/xml");
  res = client.Post("/current", "x", "text/plain");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 405);
  EXPECT_NE(res->body.find("UNSUPPORTED"), std::string::npos);
  res = client.Get("/sample?interval=100");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_NE(res->body.find("UNSUPPORTED"), std::string::npos);
  res = client.Get("/assets");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_NE(res->body.find("UNSUPPORTED"), std::string::npos);
  res = client.Get("/a/b/c");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 404);
  EXPECT_NE(res->body.find("INVALID_URI"), std::string::npos);
  agent.Stop();

  o.buffer_size = 8;
  EXPECT_THROW(MtconnectAgent(shop, o), InputError);
  o.buffer_size = 1024;
  o.period_s = 0;
  EXPECT_THROW(MtconnectAgent(shop, o), InputError);
}

// `trueaxis server --mtconnect` polled by an independent client.
TEST(MtconnectAgent, TheServersAgentPassesAnIndependentClientsChecks) {
  const std::string dir = TempDir("mtconnect_cli");
  auto vshop = StartVirtualShop(3);
  ASSERT_NE(vshop, nullptr);
  std::ofstream(dir + "/shop.toml") << ShopFileFor(vshop->Machines(), "127.0.0.1", WriteModel(dir + "/model.json"), "", 0.05, 0);
  const std::string out = dir + "/server.out";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    freopen(out.c_str(), "w", stdout);
    execl(TRUEAXIS_CLI_PATH, TRUEAXIS_CLI_PATH, "server", "--config", (dir + "/shop.toml").c_str(), "--quiet", "--duration-s", "120",
          "--mtconnect", "127.0.0.1:0", "--mtconnect-period-s", "0.05", "--mtconnect-buffer", "2500", nullptr);
    _exit(127);
  }
  std::string url;
  ASSERT_TRUE(WaitFor([&] {
    std::ifstream f(out);
    const std::string text((std::istreambuf_iterator<char>(f)), {});
    std::smatch m;
    if (std::regex_search(text, m, std::regex(R"(MTConnect agent: (http://127\.0\.0\.1:[0-9]+)/probe)"))) url = m[1].str();
    return !url.empty();
  }));
  const std::string client = std::string("/usr/bin/python3 ") + TRUEAXIS_SOURCE_DIR + "/tests/server/peers/mtconnect_client.py " + url;
  auto r = trueaxis::testing::RunShell(client + " check vm-0000,vm-0001,vm-0002 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\nok"), std::string::npos) << r.output;
  std::printf("%s", r.output.c_str());
  vshop->SetFault(2, TerminalFault::kDown);  // its terminal stops answering
  r = trueaxis::testing::RunShell(client + " unavailable vm-0002 vm-0000 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::printf("%s", r.output.c_str());
  kill(pid, SIGTERM);
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

TEST(MtconnectAgent, BadOptionsAreRefusedBeforeTheServerStarts) {
  const std::string src = TRUEAXIS_SOURCE_DIR;
  for (const auto& [args, field] : std::vector<std::pair<std::string, std::string>>{
           {"--mtconnect 127.0.0.1", "--mtconnect"},
           {"--mtconnect 127.0.0.1:99999", "--mtconnect"},
           {"--mtconnect 127.0.0.1:0 --mtconnect-period-s 0", "--mtconnect-period-s"},
           {"--mtconnect 127.0.0.1:0 --mtconnect-buffer 3", "--mtconnect-buffer"}}) {
    const auto r = trueaxis::testing::RunCli("server --config " + src + "/examples/run/virtual.toml " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(field), std::string::npos) << args << "\n" << r.output;
  }
}

}  // namespace
}  // namespace trueaxis::server
