// One machine, two HTTP servers, one vocabulary: the workshop server's control API
// (server::HttpApi) and the web front end over the same shop (web::WebServer on a ShopBackend)
// answer GET /api/machines/{id} with the same fields for a machine, its axes, channels, alarms
// and model. Fails when either server renames, adds or drops a field the other does not.
#include <httplib.h>

#include <set>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "../server/shop_fixture.hpp"
#include "trueaxis/server/http_api.hpp"
#include "trueaxis/server/shop.hpp"
#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/shop_backend.hpp"
#include "trueaxis/web/web_server.hpp"

namespace trueaxis::web {
namespace {

using server::testing::ConfigFor;
using server::testing::StartVirtualShop;
using server::testing::TempDir;
using server::testing::WaitFor;
using server::testing::WriteModel;

std::set<std::string> Keys(const nlohmann::json& object) {
  std::set<std::string> keys;
  for (const auto& [key, value] : object.items()) keys.insert(key);
  return keys;
}

// What each server says beyond the machine's shared fields (docs/server.md, docs/web.md).
const std::set<std::string> kServerOnly = {"endpoint", "alarm_bits", "unacknowledged", "last_fault", "cycles",
                                           "complete_cycles", "faults", "connects", "overruns", "last_latency_ms"};
const std::set<std::string> kServerModelOnly = {"slot"};
const std::set<std::string> kWebModelOnly = {"label", "available", "figures"};

std::set<std::string> Without(std::set<std::string> keys, const std::set<std::string>& extra) {
  for (const auto& k : extra) keys.erase(k);
  return keys;
}

TEST(OneDialect, ControlApiAndWebFrontEndDescribeAShopMachineWithTheSameFields) {
  const std::string dir = TempDir("web_one_dialect");
  auto vshop = StartVirtualShop(2);
  ASSERT_TRUE(vshop);
  const server::ShopConfig config = ConfigFor(*vshop, WriteModel(dir + "/model.json", 1.0));
  server::Shop shop(config, nullptr);
  shop.Start();
  ShopBackendOptions o;
  o.sample_period_s = 0.05;
  ShopBackend backend(shop, nullptr, o);
  backend.Start();
  const std::string name = config.machines[0].name;
  ASSERT_TRUE(WaitFor([&] { return shop.Machine(name) && shop.Machine(name)->connected; }));

  server::HttpApi api(shop, "127.0.0.1", 0);
  std::string error;
  ASSERT_TRUE(api.Start(&error)) << error;
  AccessDb access(dir + "/users.db");
  access.AddUser("viewer", Role::kViewer, "viewer-pass-1", HashCost::kMinimum);
  WebServerOptions wo;
  wo.port = 0;
  WebServer web(backend, access, wo);
  web.Start();

  httplib::Client control("127.0.0.1", api.port());
  httplib::Client browser("127.0.0.1", web.port());
  const auto login = browser.Post("/api/login", R"({"user": "viewer", "password": "viewer-pass-1"})", "application/json");
  ASSERT_TRUE(login);
  ASSERT_EQ(login->status, 200) << login->body;
  const std::string set_cookie = login->get_header_value("Set-Cookie");
  const httplib::Headers session{{"Cookie", set_cookie.substr(0, set_cookie.find(';'))}};

  const auto a = control.Get("/api/machines/" + name);
  const auto w = browser.Get("/api/machines/" + name, session);
  const auto wl = browser.Get("/api/machines?sort=id", session);
  ASSERT_TRUE(a && w && wl);
  ASSERT_EQ(a->status, 200) << a->body;
  ASSERT_EQ(w->status, 200) << w->body;
  const auto from_api = nlohmann::json::parse(a->body);
  const auto from_web = nlohmann::json::parse(w->body);
  const auto from_web_list = nlohmann::json::parse(wl->body)["machines"][0];

  // The machine: the same top-level fields, but the server's link counters.
  EXPECT_EQ(Without(Keys(from_api), kServerOnly), Keys(from_web));
  EXPECT_EQ(Keys(from_web_list), Keys(from_web));  // the overview row is the same object
  EXPECT_EQ(Without(Keys(from_api["model"]), kServerModelOnly), Without(Keys(from_web["model"]), kWebModelOnly));
  EXPECT_EQ(Keys(from_web_list["model"]), Without(Keys(from_web["model"]), kWebModelOnly));
  // Axes and channels: the same fields, in both.
  ASSERT_EQ(from_api["axes"].size(), config.machines[0].axes.size());
  ASSERT_EQ(from_web["axes"].size(), from_api["axes"].size());
  for (std::size_t i = 0; i < from_api["axes"].size(); ++i) {
    EXPECT_EQ(Keys(from_api["axes"][i]), Keys(from_web["axes"][i]));
    EXPECT_EQ(from_api["axes"][i]["name"], from_web["axes"][i]["name"]);
    EXPECT_EQ(from_api["axes"][i]["enabled"], from_web["axes"][i]["enabled"]);
    EXPECT_TRUE(from_web["axes"][i]["position_mm"].is_number()) << from_web["axes"][i];
    EXPECT_TRUE(from_web["axes"][i]["correction_um"].is_number()) << from_web["axes"][i];
  }
  ASSERT_FALSE(from_api["channels"].empty());
  ASSERT_EQ(from_web["channels"].size(), from_api["channels"].size());
  for (std::size_t i = 0; i < from_api["channels"].size(); ++i) {
    EXPECT_EQ(Keys(from_api["channels"][i]), Keys(from_web["channels"][i]));
    EXPECT_EQ(from_api["channels"][i]["name"], from_web["channels"][i]["name"]);
  }
  // The values that do not move from one read to the next are equal, with their types.
  for (const char* key : {"id", "name", "coolant", "coolant_override"}) EXPECT_EQ(from_api[key], from_web[key]) << key;
  for (const char* key : {"revision", "sha256", "file"}) EXPECT_EQ(from_api["model"][key], from_web["model"][key]) << key;
  EXPECT_TRUE(from_web["alarms"].is_array());
  EXPECT_TRUE(from_api["alarms"].is_array());
  EXPECT_TRUE(from_api["unacknowledged"].is_array());

  web.Stop();
  api.Stop();
  backend.Stop();
  shop.Stop();
  vshop->Stop();
}

}  // namespace
}  // namespace trueaxis::web
