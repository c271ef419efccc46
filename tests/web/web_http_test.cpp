// HTTP tests of every endpoint of the web front end, and of what an attacker or a broken client
// sends: wrong passwords, lockout, forged and expired sessions, missing CSRF tokens, role
// escalation, path traversal, oversized and malformed bodies, slow-loris connections.
#include <atomic>
#include <thread>
#include <vector>

#include "raw_socket.hpp"
#include "web_fixture.hpp"

namespace trueaxis::web::testing {
namespace {

using nlohmann::json;

bool AuditHas(const AccessDb& db, const std::string& action, const std::string& outcome_prefix, const std::string& user) {
  for (const auto& e : db.RecentAudit(200))
    if (e.action == action && e.outcome.rfind(outcome_prefix, 0) == 0 && e.user == user && !e.remote.empty()) return true;
  return false;
}

TEST_F(WebServerTest, LoginSetsAStrictHttpOnlyCookieAndGivesTheCsrfToken) {
  auto r = Login("admin", kAdminPassword);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  const std::string cookie = r->get_header_value("Set-Cookie");
  EXPECT_NE(cookie.find("ta_session="), std::string::npos);
  EXPECT_NE(cookie.find("HttpOnly"), std::string::npos);
  EXPECT_NE(cookie.find("SameSite=Strict"), std::string::npos);
  EXPECT_EQ(cookie.find("Secure"), std::string::npos) << "no TLS here";
  const json j = Json(r);
  EXPECT_EQ(j["role"], "admin");
  EXPECT_EQ(j["csrf"].get<std::string>().size(), 64u);
  EXPECT_TRUE(AuditHas(*access_, "login", "ok", "admin"));
}

TEST_F(WebServerTest, WrongPasswordAndUnknownUserGetTheSame401) {
  auto wrong = Login("admin", "not-the-password");
  auto unknown = Login("nobody", "whatever-pass");
  ASSERT_TRUE(wrong && unknown);
  EXPECT_EQ(wrong->status, 401);
  EXPECT_EQ(unknown->status, 401);
  EXPECT_EQ(Json(wrong)["error"], Json(unknown)["error"]);
  EXPECT_TRUE(wrong->get_header_value("Set-Cookie").empty());
  bool audited = false;
  for (const auto& e : access_->RecentAudit(20))
    audited |= e.action == "login" && e.target == "admin" && e.outcome.rfind("failed", 0) == 0;
  EXPECT_TRUE(audited);
  for (const auto& e : access_->RecentAudit(20)) EXPECT_EQ(e.detail.find("not-the-password"), std::string::npos);
}

class LockoutTest : public WebServerTest {
 protected:
  LockoutTest() {
    options_.login.max_failures = 3;
    options_.login.lockout_s = 1.5;
  }
};

TEST_F(LockoutTest, AfterNFailuresEvenTheRightPasswordIsRefusedUntilTheLockoutEnds) {
  for (int i = 0; i < 3; ++i) {
    auto r = Login("op", "wrong-" + std::to_string(i));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 401);
  }
  auto locked = Login("op", kOperatorPassword);
  ASSERT_TRUE(locked);
  EXPECT_EQ(locked->status, 429);
  EXPECT_FALSE(locked->get_header_value("Retry-After").empty());
  EXPECT_TRUE(locked->get_header_value("Set-Cookie").empty());
  // Other users are not locked out by op's failures.
  EXPECT_EQ(Login("viewer", kViewerPassword)->status, 200);
  std::this_thread::sleep_for(std::chrono::milliseconds(1700));
  EXPECT_EQ(Login("op", kOperatorPassword)->status, 200);
}

TEST_F(WebServerTest, ForgedMissingAndLoggedOutSessionsAre401) {
  EXPECT_EQ(Client()->Get("/api/machines")->status, 401);
  httplib::Headers forged{{"Cookie", "ta_session=" + std::string(64, 'a')}};
  EXPECT_EQ(Client()->Get("/api/machines", forged)->status, 401);
  httplib::Headers garbage{{"Cookie", "ta_session=../../etc/passwd; other=1"}};
  EXPECT_EQ(Client()->Get("/api/session", garbage)->status, 401);
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  EXPECT_EQ(Get(s, "/api/session")->status, 200);
  auto out = Post(s, "/api/logout");
  ASSERT_TRUE(out);
  EXPECT_EQ(out->status, 200);
  EXPECT_NE(out->get_header_value("Set-Cookie").find("Max-Age=0"), std::string::npos);
  EXPECT_EQ(Get(s, "/api/session")->status, 401) << "the session must end at logout";
}

TEST_F(WebServerTest, ARemovedUserOrChangedPasswordEndsTheSessionAtOnce) {
  const LoggedIn op = LoginAs("op", kOperatorPassword);
  const LoggedIn viewer = LoginAs("viewer", kViewerPassword);
  EXPECT_EQ(Get(op, "/api/session")->status, 200);
  access_->SetPassword("op", "op-new-password-2", HashCost::kMinimum);
  EXPECT_EQ(Get(op, "/api/session")->status, 401);
  EXPECT_EQ(Post(op, "/api/machines/m0001/axes/X", {{"enabled", false}})->status, 401);
  EXPECT_TRUE(access_->RemoveUser("viewer"));
  EXPECT_EQ(Get(viewer, "/api/machines")->status, 401);
  EXPECT_EQ(LoginAs("op", "op-new-password-2").csrf.size(), 64u);
}

class ShortSessionTest : public WebServerTest {
 protected:
  ShortSessionTest() { options_.sessions.idle_timeout_s = 2; }
};

TEST_F(ShortSessionTest, AnIdleSessionExpires) {
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  EXPECT_EQ(Get(s, "/api/session")->status, 200);
  std::this_thread::sleep_for(std::chrono::milliseconds(2600));
  EXPECT_EQ(Get(s, "/api/session")->status, 401);
}

class AbsoluteSessionTest : public WebServerTest {
 protected:
  AbsoluteSessionTest() { options_.sessions.absolute_timeout_s = 3; }
};

TEST_F(AbsoluteSessionTest, AnActiveSessionStillEndsAtItsAbsoluteTimeout) {
  const auto login = std::chrono::steady_clock::now();
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  for (int i = 0; i < 4; ++i) {  // active all along: the idle timeout (15 min) never applies
    EXPECT_EQ(Get(s, "/api/session")->status, 200);
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
  }
  std::this_thread::sleep_until(login + std::chrono::milliseconds(3600));
  EXPECT_EQ(Get(s, "/api/session")->status, 401);
}

TEST_F(WebServerTest, StateChangingRequestsNeedTheCsrfTokenAndTheSameOrigin) {
  const LoggedIn s = LoginAs("op", kOperatorPassword);
  const std::string path = "/api/machines/m0001/axes/X";
  const std::string body = json{{"enabled", false}}.dump();
  auto none = Client()->Post(path, s.Headers(false), body, "application/json");
  EXPECT_EQ(none->status, 403);
  httplib::Headers wrong{{"Cookie", s.cookie}, {"X-CSRF-Token", std::string(64, '0')}};
  EXPECT_EQ(Client()->Post(path, wrong, body, "application/json")->status, 403);
  httplib::Headers cross = s.Headers();
  cross.emplace("Origin", "http://evil.example");
  EXPECT_EQ(Client()->Post(path, cross, body, "application/json")->status, 403);
  EXPECT_TRUE(shop_->Machine("m0001").summary.axes[0].enabled) << "nothing refused may take effect";
  EXPECT_TRUE(AuditHas(*access_, "axis_enable", "refused", "op"));
  EXPECT_EQ(Post(s, path, json{{"enabled", false}})->status, 200);
  EXPECT_FALSE(shop_->Machine("m0001").summary.axes[0].enabled);
}

TEST_F(WebServerTest, EachRoleGetsOnlyItsOperations) {
  const LoggedIn viewer = LoginAs("viewer", kViewerPassword);
  const LoggedIn op = LoginAs("op", kOperatorPassword);
  const LoggedIn admin = LoginAs("admin", kAdminPassword);
  // Viewer: watches only.
  EXPECT_EQ(Get(viewer, "/api/machines")->status, 200);
  EXPECT_EQ(Post(viewer, "/api/machines/m0002/axes/Y", {{"enabled", false}})->status, 403);
  EXPECT_EQ(Post(viewer, "/api/machines/m0002/coolant", {{"state", "flood"}})->status, 403);
  EXPECT_EQ(Get(viewer, "/api/machines/m0002/export?from=0&to=10&format=csv")->status, 403);
  EXPECT_EQ(Get(viewer, "/api/audit")->status, 403);
  // A role in the body or a header changes nothing: the role is the session's.
  EXPECT_EQ(Post(viewer, "/api/machines/m0002/axes/Y", {{"enabled", false}, {"role", "admin"}})->status, 403);
  EXPECT_TRUE(shop_->Machine("m0002").summary.axes[1].enabled);
  // Operator: operates, but no model changes or audit log.
  EXPECT_EQ(Post(op, "/api/machines/m0002/axes/Y", {{"enabled", false}})->status, 200);
  EXPECT_EQ(Post(op, "/api/machines/m0002/model", {{"revision", "1"}})->status, 403);
  EXPECT_EQ(Post(op, "/api/machines/m0002/model/rollback")->status, 403);
  EXPECT_EQ(Get(op, "/api/audit")->status, 403);
  // Admin: everything.
  EXPECT_EQ(Post(admin, "/api/machines/m0002/model", {{"revision", "1"}})->status, 200);
  EXPECT_EQ(Get(admin, "/api/audit")->status, 200);
  EXPECT_TRUE(AuditHas(*access_, "axis_enable", "refused", "viewer"));
  EXPECT_TRUE(AuditHas(*access_, "model_load", "refused", "op"));
  EXPECT_TRUE(AuditHas(*access_, "model_load", "ok", "admin"));
}

TEST_F(WebServerTest, OverviewSortsFiltersAndPagesOnTheServer) {
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  json all = Json(Get(s, "/api/machines?limit=1000"));
  EXPECT_EQ(all["total"], machines_);
  EXPECT_EQ(all["machines"].size(), machines_);
  json page = Json(Get(s, "/api/machines?sort=id&order=desc&limit=5&offset=5"));
  ASSERT_EQ(page["machines"].size(), 5u);
  EXPECT_EQ(page["machines"][0]["id"], "m0035");
  json alarms = Json(Get(s, "/api/machines?alarms=1&limit=1000"));
  ASSERT_GT(alarms["matched"].get<int>(), 0);
  for (const auto& m : alarms["machines"]) EXPECT_FALSE(m["alarms"].empty());
  json filtered = Json(Get(s, "/api/machines?filter=HMC800"));
  ASSERT_GT(filtered["matched"].get<int>(), 0);
  for (const auto& m : filtered["machines"]) EXPECT_NE(m["name"].get<std::string>().find("hmc800"), std::string::npos);
  json by_temp = Json(Get(s, "/api/machines?sort=max_temp&order=desc&limit=1000"));
  double previous = 1e9;
  for (const auto& m : by_temp["machines"]) {
    double hottest = -1e9;
    for (const auto& c : m["channels"])
      if (c["temp_c"].is_number()) hottest = std::max(hottest, c["temp_c"].get<double>());
    EXPECT_LE(hottest, previous + 1e-9);
    previous = hottest;
  }
  EXPECT_EQ(Get(s, "/api/machines?sort=password")->status, 400);
  EXPECT_EQ(Get(s, "/api/machines?limit=-3")->status, 400);
  EXPECT_EQ(Get(s, "/api/machines?offset=abc")->status, 400);
}

TEST_F(WebServerTest, MachineLiveAndHistoryEndpoints) {
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  json m = Json(Get(s, "/api/machines/m0001"));
  EXPECT_EQ(m["id"], "m0001");
  EXPECT_EQ(m["axes"].size(), 3u);
  EXPECT_FALSE(m["model"]["revision"].get<std::string>().empty());
  EXPECT_FALSE(m["model"]["figures"].empty());
  EXPECT_EQ(Get(s, "/api/machines/m9999")->status, 404);
  json live = Json(Get(s, "/api/machines/m0001/live?after=0"));
  const auto last = live["last_seq"].get<std::uint64_t>();
  ASSERT_GE(live["samples"].size(), 6u);
  EXPECT_EQ(live["samples"].back()["seq"], last);
  // Only what the client has not seen: nothing new, then exactly the new tick.
  EXPECT_TRUE(Json(Get(s, "/api/machines/m0001/live?after=" + std::to_string(last)))["samples"].empty());
  shop_->Tick(std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count() + 1);
  json next = Json(Get(s, "/api/machines/m0001/live?after=" + std::to_string(last)));
  ASSERT_EQ(next["samples"].size(), 1u);
  EXPECT_EQ(next["samples"][0]["seq"], last + 1);
  json h = Json(Get(s, "/api/machines/m0001/history?from=1000&to=4600&points=50"));
  ASSERT_EQ(h["temperatures"].size(), 4u);
  EXPECT_EQ(h["temperatures"][0]["t"].size(), 50u);
  EXPECT_TRUE(h["decimated"].get<bool>());
  EXPECT_EQ(Get(s, "/api/machines/m0001/history?from=10&to=5")->status, 400);
  EXPECT_EQ(Get(s, "/api/machines/m0001/history?from=10")->status, 400);
  EXPECT_EQ(Get(s, "/api/machines/m0001/history?from=nan&to=5")->status, 400);
}

TEST_F(WebServerTest, OperationsTakeEffectAndAreAudited) {
  const LoggedIn op = LoginAs("op", kOperatorPassword);
  const LoggedIn admin = LoginAs("admin", kAdminPassword);
  EXPECT_EQ(Post(op, "/api/machines/m0003/coolant", {{"state", "mist"}})->status, 200);
  EXPECT_EQ(shop_->Machine("m0003").summary.coolant_override, "mist");
  EXPECT_EQ(Post(op, "/api/machines/m0003/coolant", {{"state", "lava"}})->status, 400);
  EXPECT_EQ(Post(op, "/api/machines/m0003/coolant", {{"state", ""}})->status, 200);
  EXPECT_EQ(shop_->Machine("m0003").summary.coolant_override, "");
  EXPECT_EQ(Post(op, "/api/machines/m0003/axes/Q", {{"enabled", true}})->status, 404);
  // Model: load 3, roll back to what was before.
  const std::string before = shop_->Machine("m0003").summary.model.revision;
  EXPECT_EQ(Post(admin, "/api/machines/m0003/model", {{"revision", "3"}})->status, 200);
  EXPECT_EQ(shop_->Machine("m0003").summary.model.revision, "3");
  EXPECT_EQ(Json(Post(admin, "/api/machines/m0003/model/rollback"))["revision"], before);
  EXPECT_EQ(Post(admin, "/api/machines/m0003/model", {{"revision", "99"}})->status, 404);
  // Alarms: acknowledge once; twice is a conflict.
  json alarms = Json(Get(op, "/api/alarms"));
  ASSERT_FALSE(alarms["alarms"].empty());
  const std::string id = alarms["alarms"][0]["id"];
  EXPECT_EQ(Post(op, "/api/alarms/" + id + "/ack")->status, 200);
  EXPECT_EQ(Post(op, "/api/alarms/" + id + "/ack")->status, 409);
  EXPECT_EQ(Post(op, "/api/alarms/nope:1/ack")->status, 404);
  json after = Json(Get(op, "/api/alarms"));
  for (const auto& a : after["alarms"])
    if (a["id"] == id) EXPECT_EQ(a["acknowledged_by"], "op");
  // Export: a CSV download, audited.
  auto csv = Get(op, "/api/machines/m0003/export?from=1000&to=1010&format=csv&table=compensation");
  ASSERT_TRUE(csv);
  EXPECT_EQ(csv->status, 200);
  EXPECT_NE(csv->get_header_value("Content-Disposition").find("attachment"), std::string::npos);
  EXPECT_EQ(csv->body.rfind("time_s,time_utc,X_correction_um", 0), 0u) << csv->body.substr(0, 80);
  EXPECT_EQ(Get(op, "/api/machines/m0003/export?from=0&to=10&format=pdf")->status, 400);
  // The audit log says who, what, where, and how it ended.
  json log = Json(Get(admin, "/api/audit?limit=100"));
  std::set<std::string> actions;
  for (const auto& e : log["entries"]) {
    actions.insert(e["action"].get<std::string>());
    EXPECT_NE(e["remote"].get<std::string>().find("127.0.0.1:"), std::string::npos);
    EXPECT_FALSE(e["time_utc"].get<std::string>().empty());
  }
  for (const char* a : {"coolant_override", "model_load", "model_rollback", "alarm_ack", "export", "login"})
    EXPECT_TRUE(actions.count(a)) << a;
}

TEST_F(WebServerTest, BadBodiesGet4xxJsonAndTheServerStaysUp) {
  const LoggedIn op = LoginAs("op", kOperatorPassword);
  const std::string path = "/api/machines/m0001/axes/X";
  auto malformed = Client()->Post(path, op.Headers(), "{\"enabled\": tru", "application/json");
  EXPECT_EQ(malformed->status, 400);
  EXPECT_TRUE(Json(malformed).contains("error"));
  EXPECT_EQ(Client()->Post(path, op.Headers(), "[1,2]", "application/json")->status, 400);
  EXPECT_EQ(Client()->Post(path, op.Headers(), "{\"enabled\": \"yes\"}", "application/json")->status, 400);
  EXPECT_EQ(Client()->Post(path, op.Headers(), "{}", "application/json")->status, 400);
  EXPECT_EQ(Client()->Post(path, op.Headers(), "enabled=false", "application/x-www-form-urlencoded")->status, 415);
  auto big = Client()->Post(path, op.Headers(), std::string(64 * 1024, ' ') + "{}", "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  EXPECT_EQ(Client()->Post("/api/login", std::string(100000, 'x'), "application/json")->status, 413);
  EXPECT_EQ(Client()->Post("/api/login", "{\"user\": 3}", "application/json")->status, 400);
  EXPECT_EQ(RawExchange(server_->port(), "GARBAGE\r\n\r\n").rfind("HTTP/1.1 400", 0), 0u);
  EXPECT_EQ(RawExchange(server_->port(), "GET /api/session HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: -5\r\n\r\n").rfind("HTTP/1.1 4", 0), 0u);
  EXPECT_EQ(Client()->Delete("/api/machines")->status, 404);
  EXPECT_EQ(Get(op, "/api/machines?filter=" + std::string(20000, 'a'))->status, 414);
  EXPECT_EQ(RawExchange(server_->port(), "GET /login.html HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Long: " + std::string(20000, 'b') +
                                             "\r\n\r\n").rfind("HTTP/1.1 400", 0), 0u);
  EXPECT_EQ(Get(op, "/api/session")->status, 200) << "the server keeps serving";
}

TEST_F(WebServerTest, StaticFilesAreServedByExactNameOnlyWithSecurityHeaders) {
  auto page = Client()->Get("/overview.html");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  const std::string csp = page->get_header_value("Content-Security-Policy");
  EXPECT_NE(csp.find("script-src 'self'"), std::string::npos);
  EXPECT_EQ(csp.find("unsafe-inline"), std::string::npos);
  EXPECT_NE(csp.find("frame-ancestors 'none'"), std::string::npos);
  EXPECT_EQ(page->get_header_value("X-Frame-Options"), "DENY");
  EXPECT_EQ(page->body.find("<script>"), std::string::npos) << "no inline script";
  EXPECT_EQ(Client()->Get("/vendor/chart.min.js")->status, 200);
  for (const char* raw : {"/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd", "/..%2f..%2f..%2fetc%2fpasswd",
                          "/vendor/../../../../etc/passwd", "//etc/passwd", "/static/../web_server.cpp",
                          "/overview.html%00.js", "/.%2e/.%2e/etc/passwd", "/vendor/chart.js/../../../etc/passwd"}) {
    const std::string answer = RawExchange(server_->port(), std::string("GET ") + raw + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
    EXPECT_TRUE(answer.rfind("HTTP/1.1 404", 0) == 0 || answer.rfind("HTTP/1.1 400", 0) == 0) << raw << "\n" << answer.substr(0, 80);
    EXPECT_EQ(answer.find("root:"), std::string::npos) << raw;
  }
}

TEST_F(WebServerTest, SlowLorisConnectionsDoNotStopTheServerServingOthers) {
  // Eight connections that trickle a request one byte at a time and never finish it.
  SlowClients loris(server_->port(), 8);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const LoggedIn s = LoginAs("viewer", kViewerPassword);
  for (int i = 0; i < 10; ++i) {
    auto r = Get(s, "/api/machines/m0001/live?after=0");
    ASSERT_TRUE(r) << "the server stopped answering while slow clients were connected";
    EXPECT_EQ(r->status, 200);
  }
  loris.Stop();
}

TEST_F(WebServerTest, ABurstOfConnectionsAtOnceIsServedNotReset) {
  // cpp-httplib listens with a backlog of 5 unless told otherwise: a burst was reset (measured).
  std::atomic<int> answered{0};
  std::vector<std::thread> burst;
  for (int i = 0; i < 300; ++i)
    burst.emplace_back([&] {
      auto r = Client()->Get("/login.html");
      if (r && r->status == 200) ++answered;
    });
  for (auto& t : burst) t.join();
  EXPECT_EQ(answered.load(), 300);
}

}  // namespace
}  // namespace trueaxis::web::testing
