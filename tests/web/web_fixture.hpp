#pragma once
// A web server on 127.0.0.1 (any free port) over a small synthetic shop, with one user per role
// (passwords hashed at libsodium's minimum cost to keep the tests fast), and an HTTP client
// that logs in and carries the session cookie and CSRF token. Everything stops with the test.
#include <httplib.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "store/test_dir.hpp"
#include "trueaxis/web/access_db.hpp"
#include "trueaxis/web/synthetic_shop.hpp"
#include "trueaxis/web/web_server.hpp"

namespace trueaxis::web::testing {

inline const char* kAdminPassword = "admin-pass-1";
inline const char* kOperatorPassword = "operator-pass-1";
inline const char* kViewerPassword = "viewer-pass-1";

struct LoggedIn {
  std::string cookie;  // "ta_session=…"
  std::string csrf;
  httplib::Headers Headers(bool with_csrf = true) const {
    httplib::Headers h{{"Cookie", cookie}};
    if (with_csrf) h.emplace("X-CSRF-Token", csrf);
    return h;
  }
};

class WebServerTest : public trueaxis::testing::TempDirTest {
 protected:
  // Override before SetUp runs (in the test's constructor) to change the server.
  WebServerOptions options_;
  std::size_t machines_ = 40;

  void SetUp() override {
    TempDirTest::SetUp();
    access_ = std::make_unique<AccessDb>((dir_ / "users.db").string());
    access_->AddUser("admin", Role::kAdmin, kAdminPassword, HashCost::kMinimum);
    access_->AddUser("op", Role::kOperator, kOperatorPassword, HashCost::kMinimum);
    access_->AddUser("viewer", Role::kViewer, kViewerPassword, HashCost::kMinimum);
    shop_ = std::make_unique<SyntheticShop>(machines_);
    const double now = std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
    for (int k = 5; k >= 0; --k) shop_->Tick(now - k);
    options_.port = 0;
    options_.read_timeout_s = options_.read_timeout_s == 5 ? 2 : options_.read_timeout_s;
    server_ = std::make_unique<WebServer>(*shop_, *access_, options_);
    server_->Start();
  }
  void TearDown() override {
    server_.reset();
    shop_.reset();
    access_.reset();
    TempDirTest::TearDown();
  }

  std::unique_ptr<httplib::Client> Client() const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    c->set_read_timeout(10, 0);
    return c;
  }
  httplib::Result Login(const std::string& user, const std::string& password) const {
    return Client()->Post("/api/login", nlohmann::json{{"user", user}, {"password", password}}.dump(), "application/json");
  }
  // As a person at the login page: a "busy" or "other logins being checked" answer (many logins at
  // once) says to try again in a second.
  httplib::Result LoginRetrying(const std::string& user, const std::string& password) const {
    std::minstd_rand jitter(std::random_device{}());
    for (int attempt = 1;; ++attempt) {
      auto r = Login(user, password);
      const bool again = r && (r->status == 503 || (r->status == 429 && r->get_header_value("Retry-After") == "1"));
      if (!again || attempt == 60) return r;
      std::this_thread::sleep_for(std::chrono::milliseconds(500 + jitter() % 1000));
    }
  }
  LoggedIn LoginAs(const std::string& user, const std::string& password) const {
    auto r = LoginRetrying(user, password);
    EXPECT_TRUE(r) << "no answer";
    if (!r) return {};
    EXPECT_EQ(r->status, 200) << r->body;
    const std::string set = r->get_header_value("Set-Cookie");
    LoggedIn s;
    s.cookie = set.substr(0, set.find(';'));
    s.csrf = nlohmann::json::parse(r->body).value("csrf", "");
    return s;
  }
  httplib::Result Get(const LoggedIn& s, const std::string& path) const { return Client()->Get(path, s.Headers(false)); }
  httplib::Result Post(const LoggedIn& s, const std::string& path, const nlohmann::json& body = nlohmann::json::object()) const {
    return Client()->Post(path, s.Headers(), body.dump(), "application/json");
  }
  static nlohmann::json Json(const httplib::Result& r) {
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/json") << r->status << " " << r->body;
    return nlohmann::json::parse(r->body, nullptr, false);
  }

  std::unique_ptr<AccessDb> access_;
  std::unique_ptr<SyntheticShop> shop_;
  std::unique_ptr<WebServer> server_;
};

}  // namespace trueaxis::web::testing
