// The web front end under attack, over real sockets on 127.0.0.1: parallel password guesses
// against the lockout, a flood of attempts on a locked name (audit log), chunked and length-less
// bodies past the size limit, a foreign Host (DNS rebinding), an Origin of another scheme, media
// types that only start like JSON, slow-header connections.
#include <atomic>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "raw_socket.hpp"
#include "web_fixture.hpp"

namespace trueaxis::web::testing {
namespace {

using nlohmann::json;

int StatusOf(const std::string& answer) { return answer.rfind("HTTP/1.1 ", 0) == 0 ? std::atoi(answer.c_str() + 9) : 0; }

struct Answer {
  int status = 0;  // 0: no answer
  std::string retry_after, set_cookie, body;
};

// Starts the logins at the same moment (threads held at a gate), each on its own connection.
std::vector<Answer> ParallelLogins(int port, const std::vector<std::pair<std::string, std::string>>& tries) {
  std::vector<Answer> results(tries.size());
  std::atomic<bool> go{false};
  std::atomic<std::size_t> waiting{0};
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < tries.size(); ++i)
    threads.emplace_back([&, i] {
      httplib::Client c("127.0.0.1", port);
      c.set_read_timeout(60, 0);
      const std::string body = json{{"user", tries[i].first}, {"password", tries[i].second}}.dump();
      ++waiting;
      while (!go.load()) std::this_thread::yield();
      if (auto r = c.Post("/api/login", body, "application/json"))
        results[i] = {r->status, r->get_header_value("Retry-After"), r->get_header_value("Set-Cookie"), r->body};
    });
  while (waiting.load() < tries.size()) std::this_thread::yield();
  go = true;
  for (auto& t : threads) t.join();
  return results;
}

// Three failures lock a name for a minute.
class GuessingTest : public WebServerTest {
 protected:
  GuessingTest() {
    options_.login.max_failures = 3;
    options_.login.lockout_s = 60;
    options_.worker_threads = 40;  // every request of the burst is served at once
  }
};

TEST_F(GuessingTest, ParallelGuessesCannotPassTheLockout) {
  // A hash at the real cost (tenths of a second): the window the guesses raced through.
  access_->AddUser("slow", Role::kOperator, "slow-pass-1", HashCost::kInteractive);
  std::vector<std::pair<std::string, std::string>> tries;
  for (int i = 0; i < 29; ++i) tries.emplace_back("slow", "guess-" + std::to_string(i));
  tries.emplace_back("slow", "slow-pass-1");  // the last one right
  const auto results = ParallelLogins(server_->port(), tries);
  int checked = 0, refused = 0, wrong = 0, right = 0;
  for (const auto& r : results) {
    if (r.status == 401 || r.status == 200) ++checked;
    if (r.status == 401) ++wrong;
    if (r.status == 200) ++right;
    if (r.status == 429) {
      ++refused;
      EXPECT_FALSE(r.retry_after.empty());
      EXPECT_TRUE(r.set_cookie.empty());
    }
    EXPECT_TRUE(r.status == 401 || r.status == 200 || r.status == 429) << r.status << " " << r.body;
  }
  // At most max_failures passwords of the name were checked, however many arrived at once: the
  // right password passes only if it was among them, as it would one after another.
  EXPECT_LE(checked, 3) << wrong << " wrong and " << right << " right passwords were checked";
  EXPECT_EQ(refused, 30 - checked);
  if (right == 0) {
    EXPECT_EQ(wrong, 3);
    auto after = Login("slow", "slow-pass-1");
    ASSERT_TRUE(after);
    EXPECT_EQ(after->status, 429) << "the name is locked: even the right password is refused";
  }
}

class HashBoundTest : public WebServerTest {
 protected:
  HashBoundTest() {
    options_.login.max_hashes_in_flight = 2;
    options_.worker_threads = 40;
  }
};

TEST_F(HashBoundTest, PasswordChecksBeyondTheBoundAreRefusedAtOnceWithRetryAfter) {
  // Twelve different names at once: no name is locked, but only two 64 MiB hashes may run at a time.
  std::vector<std::pair<std::string, std::string>> tries;
  for (int i = 0; i < 12; ++i) tries.emplace_back("nobody-" + std::to_string(i), "whatever-pass");
  int busy = 0, checked = 0;
  for (const auto& r : ParallelLogins(server_->port(), tries)) {
    EXPECT_TRUE(r.status == 401 || r.status == 503) << r.status << " " << r.body;
    if (r.status == 401) ++checked;
    if (r.status == 503) {
      ++busy;
      EXPECT_EQ(r.retry_after, "1");
      EXPECT_NE(json::parse(r.body, nullptr, false).value("error", "").find("busy"), std::string::npos) << r.body;
    }
  }
  EXPECT_GE(busy, 1) << "twelve hashes ran at once";
  EXPECT_GE(checked, 2);
  // The bound frees itself: a login afterwards is checked.
  EXPECT_EQ(Login("admin", kAdminPassword)->status, 200);
}

TEST_F(GuessingTest, AttemptsOnALockedNameAreOneAuditRowWithACount) {
  for (int i = 0; i < 3; ++i) EXPECT_EQ(Login("op", "wrong-" + std::to_string(i))->status, 401);
  int refused = 0;
  for (int i = 0; i < 150; ++i) refused += Login("op", "wrong-again")->status == 429;
  EXPECT_EQ(refused, 150);
  server_->Stop();  // writes the burst's last count
  int rows = 0;
  std::string detail;
  for (const auto& e : access_->RecentAudit(1000))
    if (e.action == "login" && e.outcome == "refused: locked out") {
      ++rows;
      detail = e.detail;
      EXPECT_EQ(e.target, "op");
      EXPECT_FALSE(e.remote.empty());
    }
  EXPECT_EQ(rows, 1) << "one row for the burst, not one per request";
  EXPECT_EQ(detail.rfind("150 attempts refused from ", 0), 0u) << detail;
  int failed = 0;
  for (const auto& e : access_->RecentAudit(1000)) failed += e.outcome.rfind("failed", 0) == 0;
  EXPECT_EQ(failed, 3) << "each checked password keeps its own row";
}

struct Streamed {
  std::string answer;
  std::size_t sent = 0;  // body bytes the server took before it answered (or closed)
};

// Streams a chunked body of `total` bytes, or until the server stops taking it, then reads the answer.
Streamed ChunkedExchange(int port, const std::string& head, std::size_t total) {
  Streamed out;
  RawSocket s(port);
  if (!s.connected() || !s.Send(head)) return out;
  const std::string piece(64 * 1024, ' ');
  while (out.sent < total && s.Send("10000\r\n" + piece + "\r\n")) out.sent += piece.size();
  if (out.sent >= total) s.Send("0\r\n\r\n");
  out.answer = s.ReadAll();
  return out;
}

TEST_F(WebServerTest, ChunkedAndLengthlessBodiesAreRefusedBeforeTheyAreRead) {
  const std::string head = "POST /api/login HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n";
  const std::string login = json{{"user", "admin"}, {"password", kAdminPassword}}.dump();
  const std::string chunk = fmt::format("{:x}\r\n{}\r\n", login.size(), login);
  // The answer comes after the headers, before the body: the client is still sending.
  auto answer = RawExchange(server_->port(), head + "Transfer-Encoding: chunked\r\n\r\n" + chunk);
  EXPECT_EQ(StatusOf(answer), 411) << answer.substr(0, 300);
  EXPECT_NE(answer.find("Transfer-Encoding"), std::string::npos) << answer.substr(0, 300);
  // A length given and chunked anyway: chunked wins in cpp-httplib, so it is refused too.
  answer = RawExchange(server_->port(), head + "Content-Length: 40\r\nTransfer-Encoding: chunked\r\n\r\n" + chunk);
  EXPECT_EQ(StatusOf(answer), 411) << answer.substr(0, 300);
  // 64 MiB to an unauthenticated endpoint whose limit is 16 KiB: it was read whole. Now the server
  // answers at the headers and stops taking the body (closing a connection with unread data resets
  // it, which may cost the client the answer: then it could not send the whole body either).
  const Streamed big = ChunkedExchange(server_->port(), head + "Transfer-Encoding: chunked\r\n\r\n", 64u << 20);
  EXPECT_LT(big.sent, 64u << 20) << "the whole body was taken: " << big.answer.substr(0, 300);
  if (!big.answer.empty()) EXPECT_EQ(StatusOf(big.answer), 411) << big.answer.substr(0, 300);
  // No length at all: the body would be read until the client closes.
  RawSocket s(server_->port());
  ASSERT_TRUE(s.Send(head + "\r\n" + login));
  s.CloseWrite();
  answer = s.ReadAll();
  EXPECT_EQ(StatusOf(answer), 411) << answer.substr(0, 300);
  // A declared length over the limit is refused before a byte of the body is sent.
  answer = RawExchange(server_->port(), head + "Content-Length: 100000000000\r\n\r\n");
  EXPECT_EQ(StatusOf(answer), 413) << answer.substr(0, 300);
  EXPECT_EQ(Login("admin", kAdminPassword)->status, 200) << "an ordinary login still works";
}

TEST_F(WebServerTest, AForeignHostIsRefusedDnsRebinding) {
  const std::string port = std::to_string(server_->port());
  const std::string login = json{{"user", "admin"}, {"password", kAdminPassword}}.dump();
  auto post = [&](const std::string& host) {
    return RawExchange(server_->port(), "POST /api/login HTTP/1.1\r\nHost: " + host + "\r\nOrigin: http://" + host +
                                            "\r\nContent-Type: application/json\r\nContent-Length: " +
                                            std::to_string(login.size()) + "\r\n\r\n" + login);
  };
  auto answer = post("evil.example:" + port);
  EXPECT_EQ(StatusOf(answer), 403) << answer.substr(0, 300);
  EXPECT_NE(answer.find("field 'Host'"), std::string::npos) << answer.substr(0, 300);
  EXPECT_EQ(answer.find("Set-Cookie"), std::string::npos);
  answer = RawExchange(server_->port(), "GET /api/session HTTP/1.1\r\nHost: evil.example:" + port + "\r\n\r\n");
  EXPECT_EQ(StatusOf(answer), 403) << answer.substr(0, 300);
  answer = RawExchange(server_->port(), "GET /overview.html HTTP/1.1\r\nHost: EVIL.example\r\n\r\n");
  EXPECT_EQ(StatusOf(answer), 403) << answer.substr(0, 300);
  // This computer's names and addresses are served.
  for (const std::string host : {"127.0.0.1:" + port, "localhost:" + port, "LOCALHOST:" + port})
    EXPECT_EQ(StatusOf(post(host)), 200) << host;
}

class HostNameTest : public WebServerTest {
 protected:
  HostNameTest() { options_.host_names = {"cnc-monitor.plant.example"}; }
};

TEST_F(HostNameTest, ANameGivenWithWebHostNameIsServed) {
  const std::string port = std::to_string(server_->port());
  auto answer = RawExchange(server_->port(), "GET /login.html HTTP/1.1\r\nHost: cnc-monitor.plant.example:" + port + "\r\n\r\n");
  EXPECT_EQ(StatusOf(answer), 200) << answer.substr(0, 300);
  answer = RawExchange(server_->port(), "GET /login.html HTTP/1.1\r\nHost: cnc-monitor.evil.example:" + port + "\r\n\r\n");
  EXPECT_EQ(StatusOf(answer), 403) << answer.substr(0, 300);
}

TEST_F(WebServerTest, OriginMustMatchSchemeHostAndPort) {
  const std::string port = std::to_string(server_->port());
  const std::string login = json{{"user", "admin"}, {"password", kAdminPassword}}.dump();
  auto with_origin = [&](const std::string& origin) {
    return Client()->Post("/api/login", httplib::Headers{{"Origin", origin}}, login, "application/json");
  };
  for (const std::string& bad : std::vector<std::string>{"https://127.0.0.1:" + port, "http://127.0.0.1:1" + port, "http://127.0.0.1",
                                "http://evil.example:" + port, "null"}) {
    auto r = with_origin(bad);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 403) << bad;
    EXPECT_TRUE(r->get_header_value("Set-Cookie").empty()) << bad;
  }
  EXPECT_EQ(with_origin("http://127.0.0.1:" + port)->status, 200);
}

TEST_F(WebServerTest, OnlyJsonItselfIsAcceptedAsJson) {
  const std::string login = json{{"user", "admin"}, {"password", kAdminPassword}}.dump();
  for (const char* type : {"application/jsonfoo", "application/json-patch+json", "text/plain", "application/jso"})
    EXPECT_EQ(Client()->Post("/api/login", login, type)->status, 415) << type;
  for (const char* type : {"application/json", "application/json; charset=utf-8", "Application/JSON;charset=UTF-8"})
    EXPECT_EQ(Client()->Post("/api/login", login, type)->status, 200) << type;
}

TEST_F(WebServerTest, SlowHeadersDoNotDelayAFreshRequest) {
  // More connections than workers (32), each trickling a request a byte every 100 ms, never
  // finishing it: each held a worker as long as it kept trickling.
  SlowClients loris(server_->port(), 40);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  httplib::Client c("127.0.0.1", server_->port());
  c.set_read_timeout(5, 0);  // a bound, not a timing assertion: before, no answer while they trickled
  auto page = c.Get("/login.html");
  loris.Stop();
  ASSERT_TRUE(page) << httplib::to_string(page.error());
  EXPECT_EQ(page->status, 200);
  // A request that does not arrive whole within the read timeout is answered 408 and closed.
  RawSocket slow(server_->port());
  ASSERT_TRUE(slow.Send("GET /login.html HTTP/1.1\r\nHost: 127.0.0.1\r\n"));
  const std::string answer = slow.ReadAll();
  EXPECT_EQ(StatusOf(answer), 408) << answer.substr(0, 200);
}

}  // namespace
}  // namespace trueaxis::web::testing
