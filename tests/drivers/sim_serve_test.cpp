// `trueaxis sim serve` as a user runs it: a separate process, reached by an
// independent peer (pymodbus, mbpoll). A compensation written over MODBUS moves
// the virtual table; the server stops by itself (--duration-s).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "modbus_test_server.hpp"

namespace trueaxis::drivers {
namespace {

using testing::WaitFor;

const std::string kCli = TRUEAXIS_CLI_PATH;
const std::string kMachine = std::string(TRUEAXIS_SOURCE_DIR) + "/examples/machines/vmc850.toml";
const std::string kPeer = std::string(TRUEAXIS_SOURCE_DIR) + "/tests/drivers/peers/pymodbus_peer.py";

std::string RunCommand(const std::string& command, int* status) {
  std::string out;
  FILE* p = popen(("timeout 60 " + command + " 2>&1").c_str(), "r");
  if (!p) return out;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int raw = pclose(p);
  *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return out;
}

// A `sim serve` process whose JSON lines are collected by a reader thread.
class ServeProcess {
 public:
  bool Start(const std::string& args) {
    pipe_ = popen(("timeout 60 " + kCli + " sim serve " + args + " 2>&1").c_str(), "r");
    if (!pipe_) return false;
    reader_ = std::thread([this] {
      char line[65536];
      while (std::fgets(line, sizeof line, pipe_)) {
        std::lock_guard<std::mutex> l(mu_);
        raw_ += line;
        auto j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
        if (!j.is_discarded()) lines_.push_back(std::move(j));
      }
      std::lock_guard<std::mutex> l(mu_);
      done_ = true;
    });
    return true;
  }
  int Finish() {
    if (reader_.joinable()) reader_.join();
    const int raw = pipe_ ? pclose(pipe_) : -1;
    pipe_ = nullptr;
    return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  }
  ~ServeProcess() { Finish(); }
  std::vector<nlohmann::json> Lines() {
    std::lock_guard<std::mutex> l(mu_);
    return lines_;
  }
  std::string Raw() {
    std::lock_guard<std::mutex> l(mu_);
    return raw_;
  }
  bool Done() {
    std::lock_guard<std::mutex> l(mu_);
    return done_;
  }
  // The last line of `kind`, or null.
  nlohmann::json Last(const std::string& kind) {
    std::lock_guard<std::mutex> l(mu_);
    for (auto it = lines_.rbegin(); it != lines_.rend(); ++it)
      if ((*it)["kind"] == kind) return *it;
    return nullptr;
  }

 private:
  FILE* pipe_ = nullptr;
  std::thread reader_;
  std::mutex mu_;
  std::vector<nlohmann::json> lines_;
  std::string raw_;
  bool done_ = false;
};

TEST(SimServe, CompensationWrittenByPymodbusMovesTheVirtualTable) {
  std::mt19937 rng(std::random_device{}());
  std::unique_ptr<ServeProcess> serve;
  std::string port;
  for (int attempt = 0; attempt < 10 && !serve; ++attempt) {
    port = std::to_string(std::uniform_int_distribution<int>(20000, 59999)(rng));
    auto p = std::make_unique<ServeProcess>();
    ASSERT_TRUE(p->Start("--machine " + kMachine + " --port " + port +
                         " --program idle --duration-s 8 --status-interval-s 0.1 --json"));
    if (WaitFor([&] { return !p->Last("listening").is_null() || p->Done(); }, 20.0) && !p->Last("listening").is_null())
      serve = std::move(p);
  }
  ASSERT_NE(serve, nullptr) << "sim serve never listened";
  const auto hello = serve->Last("listening");
  EXPECT_EQ(hello["axes"], nlohmann::json({"X", "Y", "Z"}));
  EXPECT_EQ(hello["channels"][0]["unit"], 2);

  // mbpoll sees the window.
  int status = -1;
  std::string out = RunCommand("mbpoll -m tcp -a 1 -t 3 -r 1 -c 2 -1 -o 2 -p " + port + " 127.0.0.1", &status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("[2]: \t3"), std::string::npos) << out;

  // First a small + correction to take up the play, then the step we measure.
  out = RunCommand("/usr/bin/python3 " + kPeer + " " + port + " 3 10.0 0 0", &status);
  ASSERT_EQ(status, 0) << out;
  ASSERT_TRUE(WaitFor([&] {
    auto s = serve->Last("status");
    return !s.is_null() && std::abs(s["axes"]["X"]["correction_um"].get<double>() - 10.0) < 1e-9;
  }, 5.0)) << serve->Raw();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto before = serve->Last("status");
  out = RunCommand("/usr/bin/python3 " + kPeer + " " + port + " 3 40.0 0 -25.5", &status);
  ASSERT_EQ(status, 0) << out;
  auto peer = nlohmann::json::parse(out.substr(out.find('{')));
  EXPECT_EQ(peer["axis_count"], 3);
  EXPECT_EQ(peer["adam_name"], 0x6015);
  ASSERT_TRUE(WaitFor([&] {
    auto s = serve->Last("status");
    return !s.is_null() && std::abs(s["axes"]["X"]["correction_um"].get<double>() - 40.0) < 1e-9;
  }, 5.0)) << serve->Raw();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const auto after = serve->Last("status");

  EXPECT_EQ(serve->Finish(), 0) << serve->Raw();  // stopped by itself after --duration-s
  const auto final = serve->Last("final");
  ASSERT_FALSE(final.is_null()) << serve->Raw();
  EXPECT_NEAR(final["axes"]["Z"]["correction_um"].get<double>(), -25.5, 1e-9);
  // The table moved by the +30 µm step on X; the CNC's coordinate did not move.
  const double moved_um = (after["axes"]["X"]["actual_mm"].get<double>() - before["axes"]["X"]["actual_mm"].get<double>()) * 1000.0;
  EXPECT_NEAR(moved_um, 30.0, 1.0) << before.dump() << "\n" << after.dump();
  EXPECT_EQ(after["axes"]["X"]["commanded_mm"], before["axes"]["X"]["commanded_mm"]);
  EXPECT_EQ(final["compensation_writes"].get<int>(), 2);  // exactly the two vectors pymodbus wrote
}

TEST(ModbusProbe, ReadsTheServedMachineAsTheRuntimeWould) {
  std::mt19937 rng(std::random_device{}());
  std::unique_ptr<ServeProcess> serve;
  std::string port;
  for (int attempt = 0; attempt < 10 && !serve; ++attempt) {
    port = std::to_string(std::uniform_int_distribution<int>(20000, 59999)(rng));
    auto p = std::make_unique<ServeProcess>();
    ASSERT_TRUE(p->Start("--machine " + kMachine + " --port " + port + " --duration-s 3 --status-interval-s 0 --json --coolant flood"));
    if (WaitFor([&] { return !p->Last("listening").is_null() || p->Done(); }, 20.0) && !p->Last("listening").is_null())
      serve = std::move(p);
  }
  ASSERT_NE(serve, nullptr) << "sim serve never listened";
  int status = -1;
  std::string out = RunCommand(kCli + " modbus probe --port " + port + " --axes X,Y,Z --rtd-units 2,3", &status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("coolant flood, compensation enabled"), std::string::npos) << out;
  EXPECT_NE(out.find("  Z "), std::string::npos) << out;
  // 11 sensors: 7 on unit 2, 4 on unit 3 (the channel-enable mask says so).
  EXPECT_NE(out.find("u2.ch6"), std::string::npos) << out;
  EXPECT_NE(out.find("u3.ch3"), std::string::npos) << out;
  EXPECT_EQ(out.find("u3.ch4"), std::string::npos) << out;
  out = RunCommand(kCli + " modbus probe --port " + port + " --axes X,Y", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--axes"), std::string::npos) << out;
  EXPECT_EQ(serve->Finish(), 0);
  out = RunCommand(kCli + " modbus probe --port " + port, &status);  // nobody there any more
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("refused"), std::string::npos) << out;
}

TEST(SimServe, StopsCleanlyOnSigint) {
  std::mt19937 rng(std::random_device{}());
  int status = -1;
  std::string out;
  for (int attempt = 0; attempt < 5; ++attempt) {
    const std::string port = std::to_string(std::uniform_int_distribution<int>(20000, 59999)(rng));
    // SIGINT after 2 s, whether or not the machine is built by then.
    out = RunCommand("timeout --preserve-status -s INT 2 " + kCli + " sim serve --machine " + kMachine + " --port " + port + " --status-interval-s 0", &status);
    if (out.find("cannot listen") == std::string::npos) break;
  }
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("stopped:"), std::string::npos) << out;
}

TEST(SimServe, BadOptionsAreReportedWithTheFieldAndExitCode2) {
  int status = -1;
  std::string out = RunCommand(kCli + " sim serve --machine " + kMachine + " --time-scale 0", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--time-scale"), std::string::npos) << out;
  out = RunCommand(kCli + " sim serve --machine " + kMachine + " --program dance", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--program"), std::string::npos) << out;
  out = RunCommand(kCli + " sim serve --machine " + kMachine + " --coolant lava", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--coolant"), std::string::npos) << out;
  out = RunCommand(kCli + " sim serve --machine " + kMachine + " --bind not-an-ip", &status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("bind_address"), std::string::npos) << out;
}

TEST(SimServe, BusyPortIsAClearFailure) {
  testing::MockCnc cnc({"X"});
  std::string error;
  auto holder = testing::StartServer(&cnc, nullptr, {}, &error);
  ASSERT_NE(holder, nullptr) << error;
  int status = -1;
  const std::string out = RunCommand(kCli + " sim serve --machine " + kMachine + " --port " +
                                         std::to_string(holder->options().port) + " --duration-s 1",
                                     &status);
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find("cannot listen"), std::string::npos) << out;
}

}  // namespace
}  // namespace trueaxis::drivers
