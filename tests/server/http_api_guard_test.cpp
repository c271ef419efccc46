// The control API against bad input and hostile clients (sweep 2): one server per port, CSRF from a
// browser page, oversized bodies and fields, idle connections, messages that name the field and
// leak nothing; the `server` CLI's exit codes for bad ports, a bad audit log and an unreachable
// server. Real sockets on 127.0.0.1.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <thread>
#include <vector>
#include <sstream>

#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "shop_fixture.hpp"
#include "support/cli_runner.hpp"
#include "trueaxis/core/input_error.hpp"
#include "trueaxis/server/http_api.hpp"
#include "trueaxis/server/shop.hpp"

namespace trueaxis::server {
namespace {

using namespace trueaxis::server::testing;

int Connect(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  timeval tv{5, 0};  // bounded wait for the answer
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  return fd;
}

// One raw request; the answer up to the server's close (one request per connection).
std::string Raw(int port, const std::string& request) {
  const int fd = Connect(port);
  if (fd < 0) return "";
  (void)::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
  std::string answer;
  char buf[4096];
  for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;) answer.append(buf, static_cast<std::size_t>(n));
  ::close(fd);
  return answer;
}
int StatusOf(const std::string& answer) { return answer.size() > 12 ? std::atoi(answer.c_str() + 9) : 0; }
std::string BodyOf(const std::string& answer) {
  const auto p = answer.find("\r\n\r\n");
  return p == std::string::npos ? "" : answer.substr(p + 4);
}

// A shop of one virtual machine (not polled: the API's own checks are under test) and its API.
struct ApiFixture {
  std::string dir = TempDir("guard");
  std::string model = WriteModel(dir + "/m1.json", 1.0);
  std::unique_ptr<VirtualShop> vshop = StartVirtualShop(1);
  std::unique_ptr<Shop> shop;
  std::unique_ptr<HttpApi> api;
  ApiFixture() {
    ShopConfig c = ConfigFor(*vshop, model);
    c.audit_log = dir + "/audit.jsonl";
    shop = std::make_unique<Shop>(c, nullptr);
    api = std::make_unique<HttpApi>(*shop, "127.0.0.1", 0);
    std::string error;
    EXPECT_TRUE(api->Start(&error)) << error;
  }
  bool AxisYEnabled() const { return shop->Machine("vm-0000")->axes[1].enabled; }
  std::string Post(const std::string& path, const std::string& body, const std::string& extra_headers = "",
                   const std::string& type = "application/json") {
    return Raw(api->port(), "POST " + path + " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: " + type +
                                "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n" + extra_headers + "\r\n" + body);
  }
};

std::string ShopFile(const ApiFixture& f, const std::string& extra_root_keys) {
  const std::string path = f.dir + "/shop.toml";
  std::ofstream(path) << extra_root_keys << ShopFileFor(f.vshop->Machines(), "127.0.0.1", f.model, "", 0.05, 0);
  return path;
}

// Finding 1: cpp-httplib's default SO_REUSEPORT let a second server share the port.
TEST(ShopHttpApiGuard, ASecondServerOnTheSamePortIsRefused) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  HttpApi second(*f.shop, "127.0.0.1", f.api->port());
  std::string error;
  EXPECT_FALSE(second.Start(&error));
  EXPECT_NE(error.find("in use"), std::string::npos) << error;
  EXPECT_FALSE(CanListen("127.0.0.1", f.api->port(), nullptr));
  const auto cli = trueaxis::testing::RunCli("server --config " + ShopFile(f, "") + " --quiet --duration-s 1 --http-port " +
                                             std::to_string(f.api->port()));
  EXPECT_EQ(cli.exit_code, 2) << cli.output;
  EXPECT_NE(cli.output.find("field '--http-port': cannot listen on 127.0.0.1:"), std::string::npos) << cli.output;
}

// Finding 2: 70000 wrapped to 4464, -1 was ignored.
TEST(ShopHttpApiGuard, AnHttpPortOutOfRangeIsRefused) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  const std::string shop_file = ShopFile(f, "");
  for (const char* port : {"70000", "-1", "65536"}) {
    const auto cli = trueaxis::testing::RunCli("server --config " + shop_file + " --quiet --duration-s 1 --http-port " + port);
    EXPECT_EQ(cli.exit_code, 2) << port << ": " << cli.output;
    EXPECT_NE(cli.output.find("field '--http-port': " + std::string(port) + " is out of range"), std::string::npos) << cli.output;
  }
}

// Finding 3: a page in a browser could switch an axis off with a text/plain POST.
TEST(ShopHttpApiGuard, CrossSiteAndNonJsonPostsAreRefused) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  const std::string off = R"({"enabled": false, "user": "csrf"})";
  auto r = f.Post("/api/machines/vm-0000/axes/Y", off, "Origin: http://evil.example\r\n", "text/plain");
  EXPECT_EQ(StatusOf(r), 403) << r;
  EXPECT_NE(nlohmann::json::parse(BodyOf(r))["error"].get<std::string>().find("cross-origin"), std::string::npos) << r;
  r = f.Post("/api/machines/vm-0000/axes/Y", off, "", "text/plain");
  EXPECT_EQ(StatusOf(r), 415) << r;
  r = f.Post("/api/machines/vm-0000/axes/Y", off, "Origin: http://evil.example\r\n");
  EXPECT_EQ(StatusOf(r), 403) << r;
  EXPECT_TRUE(f.AxisYEnabled());
  // The server's own origin and the CLI (no Origin) still work.
  r = f.Post("/api/machines/vm-0000/axes/Y", off, "Origin: http://127.0.0.1:" + std::to_string(f.api->port()) + "\r\n",
             "application/json; charset=utf-8");
  EXPECT_EQ(StatusOf(r), 200) << r;
  EXPECT_FALSE(f.AxisYEnabled());
  // DNS rebinding: the attacker's name in Host is refused, GETs included; this computer's names pass.
  const std::string port = std::to_string(f.api->port());
  r = Raw(f.api->port(), "GET /api/stats HTTP/1.1\r\nHost: evil.example:" + port + "\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 403) << r;
  EXPECT_NE(BodyOf(r).find("field 'Host'"), std::string::npos) << r;
  for (const std::string host : {"127.0.0.1:" + port, "localhost:" + port, "[::1]:" + port, std::string("LOCALHOST")}) {
    r = Raw(f.api->port(), "GET /api/stats HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
    EXPECT_EQ(StatusOf(r), 200) << host << ": " << r;
  }
  EXPECT_TRUE(IsLoopbackAddress("127.0.0.1"));
  EXPECT_TRUE(IsLoopbackAddress("127.1.2.3"));
  EXPECT_TRUE(IsLoopbackAddress("localhost"));
  EXPECT_FALSE(IsLoopbackAddress("0.0.0.0"));
  EXPECT_FALSE(IsLoopbackAddress("10.0.3.17"));
}

// Finding 4: a 20 MB body was read and echoed back; a 5 MB "user" went into the audit log.
TEST(ShopHttpApiGuard, BodiesAndFieldsAreBoundedAndNeverEchoed) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  const std::string big = R"({"file": ")" + std::string(100000, 'a') + R"(", "user": "x"})";
  auto r = f.Post("/api/machines/vm-0000/model", big);
  EXPECT_EQ(StatusOf(r), 413) << r.substr(0, 300);
  EXPECT_LT(r.size(), 1000u);
  EXPECT_TRUE(nlohmann::json::parse(BodyOf(r)).contains("error"));
  // A body without its length would be read whole before any limit.
  r = Raw(f.api->port(), "POST /api/machines/vm-0000/model HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\n"
                         "Transfer-Encoding: chunked\r\n\r\n5\r\n{\"a\":\r\n0\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 411) << r;
  const std::string long_user = std::string(201, 'u');
  r = f.Post("/api/machines/vm-0000/model", R"({"file": ")" + f.model + R"(", "user": ")" + long_user + "\"}");
  EXPECT_EQ(StatusOf(r), 422) << r.substr(0, 300);
  EXPECT_NE(r.find("field 'user': longer than 200 characters"), std::string::npos) << r.substr(0, 300);
  EXPECT_EQ(r.find(long_user), std::string::npos);
  r = f.Post("/api/machines/vm-0000/model", R"({"file": "/)" + std::string(5000, 'f') + R"(", "user": "x"})");
  EXPECT_EQ(StatusOf(r), 422) << r.substr(0, 300);
  EXPECT_LT(r.size(), 1000u);
  EXPECT_TRUE(f.shop->ModelChanges("vm-0000").empty());
  std::ifstream audit(f.dir + "/audit.jsonl");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(audit), {}), "");
  // 200 characters (not bytes: "é" is two) are fine.
  r = f.Post("/api/machines/vm-0000/model", R"({"file": ")" + f.model + R"(", "user": ")" + std::string(100, 'a') +
                                                 [] { std::string s; for (int i = 0; i < 100; ++i) s += "é"; return s; }() + "\"}");
  EXPECT_EQ(StatusOf(r), 200) << r.substr(0, 300);
}

// A length given and the body chunked anyway: cpp-httplib read the chunks whole (1 MiB, or any
// size), past the 64 KiB limit and the Content-Length guard.
TEST(ShopHttpApiGuard, AChunkedBodyIsRefusedEvenWithAContentLength) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  const std::string head = "POST /api/machines/vm-0000/acknowledge HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                           "Content-Type: application/json\r\nContent-Length: 40\r\nTransfer-Encoding: chunked\r\n\r\n";
  const std::string body = R"({"user": "chunked"})";
  // A valid body in one chunk, sent with the headers: refused as it arrives, nothing acknowledged.
  auto r = Raw(f.api->port(), head + fmt::format("{:x}\r\n{}\r\n0\r\n\r\n", body.size(), body));
  EXPECT_EQ(StatusOf(r), 411) << r.substr(0, 300);
  EXPECT_NE(BodyOf(r).find("field 'Transfer-Encoding'"), std::string::npos) << r.substr(0, 300);
  // 64 MiB of chunks: the server stops taking them at the headers.
  const int fd = Connect(f.api->port());
  ASSERT_GE(fd, 0);
  timeval tv{5, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
  auto send_all = [fd](const std::string& s) { return ::send(fd, s.data(), s.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(s.size()); };
  std::size_t sent = 0;
  const std::string piece = "10000\r\n" + std::string(0x10000, ' ') + "\r\n";
  for (bool ok = send_all(head); ok && sent < (64u << 20);)
    if ((ok = send_all(piece))) sent += 0x10000;
  ::close(fd);
  EXPECT_LT(sent, 64u << 20) << "the whole chunked body was taken";
  // A declared length over the limit is refused before the body is read.
  r = Raw(f.api->port(), "POST /api/machines/vm-0000/acknowledge HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                         "Content-Type: application/json\r\nContent-Length: 99999999999\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 413) << r;
  EXPECT_EQ(StatusOf(f.Post("/api/machines/vm-0000/acknowledge", R"({"user": "x"})")), 200) << "a body with its length works";
}

// Finding 5: a few idle connections held every worker for seconds.
TEST(ShopHttpApiGuard, IdleConnectionsDoNotStallTheApi) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  std::vector<int> idle;
  for (int i = 0; i < 24; ++i) idle.push_back(Connect(f.api->port()));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // let the server accept them all
  httplib::Client client("127.0.0.1", f.api->port());
  client.set_connection_timeout(5);
  client.set_read_timeout(5);  // a bound, not a timing assertion: before, 24 idle clients cost 15 s
  auto res = client.Get("/api/stats");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
  for (int fd : idle)
    if (fd >= 0) ::close(fd);
}

// Clients that trickle their headers held a worker each for as long as they trickled.
TEST(ShopHttpApiGuard, SlowHeadersDoNotStallTheApi) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  std::atomic<bool> stop{false};
  std::vector<std::thread> loris;
  for (int i = 0; i < 40; ++i)
    loris.emplace_back([&, port = f.api->port()] {
      const int fd = Connect(port);
      const std::string part = "GET /api/stats HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
      for (std::size_t k = 0; fd >= 0 && !stop.load() && ::send(fd, &part[k % part.size()], 1, MSG_NOSIGNAL) == 1; ++k)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (fd >= 0) ::close(fd);
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  httplib::Client client("127.0.0.1", f.api->port());
  client.set_read_timeout(5);  // a bound: before, no answer while they trickled
  auto res = client.Get("/api/stats");
  stop = true;
  for (auto& t : loris) t.join();
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
}

// Finding 6: an audit log that cannot be appended to lost every model change silently.
TEST(ShopHttpApiGuard, AnAuditLogThatCannotBeWrittenIsRefusedAtStart) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  ShopConfig c = ConfigFor(*f.vshop, f.model);
  c.audit_log = f.dir;  // a folder
  try {
    Shop shop(c, nullptr);
    FAIL() << "a folder as the audit log was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "audit_log") << e.what();
  }
  const auto cli = trueaxis::testing::RunCli("server --config " + ShopFile(f, "audit_log = \"" + f.dir + "\"\n") +
                                             " --quiet --duration-s 1");
  EXPECT_EQ(cli.exit_code, 2) << cli.output;
  EXPECT_NE(cli.output.find("shop.toml:1: field 'audit_log': "), std::string::npos) << cli.output;
}

// Finding 7: library text, unnamed fields, empty error bodies, and a file's first bytes in an error.
TEST(ShopHttpApiGuard, ErrorsAreJsonNameTheFieldAndLeakNothing) {
  ApiFixture f;
  ASSERT_NE(f.vshop, nullptr);
  auto error_of = [](const std::string& r) {
    const auto j = nlohmann::json::parse(BodyOf(r), nullptr, false);
    return j.is_object() && j.contains("error") ? j["error"].get<std::string>() : "<no JSON error: " + r + ">";
  };
  auto r = f.Post("/api/machines/vm-0000/model", R"({"file": 5, "user": "x"})");
  EXPECT_EQ(StatusOf(r), 400);
  EXPECT_EQ(error_of(r), "request: field 'file': must be a string");
  r = f.Post("/api/machines/vm-0000/rollback", R"({"user": 123})");
  EXPECT_EQ(StatusOf(r), 400);
  EXPECT_EQ(error_of(r), "request: field 'user': must be a string");
  for (const char* v : {"\"no\"", "0"}) {
    r = f.Post("/api/machines/vm-0000/axes/Y", std::string(R"({"enabled": )") + v + R"(, "user": "x"})");
    EXPECT_EQ(StatusOf(r), 400);
    EXPECT_EQ(error_of(r), "request: field 'enabled': must be true or false");
  }
  r = f.Post("/api/machines/vm-0000/coolant", R"({"override": 5, "user": "x"})");
  EXPECT_EQ(StatusOf(r), 400);
  EXPECT_NE(error_of(r).find("field 'override'"), std::string::npos) << r;
  // Without "override" the override was cleared as if null had been sent: now it is required.
  ASSERT_EQ(StatusOf(f.Post("/api/machines/vm-0000/coolant", R"({"override": "flood", "user": "x"})")), 200);
  r = f.Post("/api/machines/vm-0000/coolant", R"({"user": "x"})");
  EXPECT_EQ(StatusOf(r), 400) << r;
  EXPECT_NE(error_of(r).find("field 'override': missing"), std::string::npos) << r;
  EXPECT_EQ(f.shop->Machine("vm-0000")->coolant_override, std::optional<std::string>("flood"));
  r = f.Post("/api/machines/vm-0000/rollback", "");
  EXPECT_EQ(StatusOf(r), 400);
  EXPECT_NE(error_of(r).find("field 'body'"), std::string::npos) << r;
  r = Raw(f.api->port(), "GET /api/nope HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 404);
  EXPECT_NE(error_of(r).find("no such endpoint"), std::string::npos) << r;
  r = Raw(f.api->port(), "DELETE /api/machines/vm-0000 HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 405);
  EXPECT_NE(error_of(r).find("not allowed"), std::string::npos) << r;
  r = Raw(f.api->port(), "GET /api/machines/vm-0000/model HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n");
  EXPECT_EQ(StatusOf(r), 405);
  EXPECT_NE(r.find("Allow: POST"), std::string::npos) << r;
  const std::string secret = f.dir + "/secret.txt";
  std::ofstream(secret) << "root:x:0:0:secret\n";
  r = f.Post("/api/machines/vm-0000/model", R"({"file": ")" + secret + R"(", "user": "x"})");
  EXPECT_EQ(StatusOf(r), 422);
  EXPECT_NE(error_of(r).find("not a model file"), std::string::npos) << r;
  EXPECT_EQ(r.find("root"), std::string::npos) << r;
  EXPECT_EQ(r.find("json.exception"), std::string::npos) << r;
}

// Finding 9: an unreachable server is not bad input (exit 1); a bad URL is (exit 2).
TEST(ShopHttpApiGuard, TheCliTellsAnUnreachableServerFromABadUrl) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);  // a free port nobody listens on
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  const int port = ntohs(a.sin_port);
  auto cli = trueaxis::testing::RunCli("server status --url http://127.0.0.1:" + std::to_string(port));
  ::close(fd);
  EXPECT_EQ(cli.exit_code, 1) << cli.output;
  EXPECT_NE(cli.output.find("cannot reach"), std::string::npos) << cli.output;
  for (const char* url : {"notaurl", "ftp://127.0.0.1:21", "http://127.0.0.1:70000"}) {
    cli = trueaxis::testing::RunCli(std::string("server status --url ") + url);
    EXPECT_EQ(cli.exit_code, 2) << url << ": " << cli.output;
    EXPECT_NE(cli.output.find("field '--url'"), std::string::npos) << cli.output;
  }
}

}  // namespace
}  // namespace trueaxis::server
