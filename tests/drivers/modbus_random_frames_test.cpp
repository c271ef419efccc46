// Property test: thousands of random (but MBAP-framed) requests with random
// unit ids, function codes, addresses and payloads never take the terminal
// down, never get an out-of-bound compensation to the CNC, and never change a
// read-only register; a well-behaved client is served normally afterwards.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "modbus_test_server.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"

namespace trueaxis::drivers {
namespace {

int Connect(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return -1;
  }
  timeval tv{1, 0};  // generous: the build machine is shared
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  return fd;
}

TEST(RandomFrames, TerminalStaysUpAndKeepsItsInvariants) {
  testing::MockCnc cnc({"X", "Y", "Z"});
  cnc.record_history = true;
  testing::MockTemperatures temps(7);
  std::string error;
  ModbusMachineServerOptions o;
  o.max_abs_compensation_um = 100.0;
  auto server = testing::StartServer(&cnc, &temps, o, &error);
  ASSERT_NE(server, nullptr) << error;
  const int port = server->options().port;

  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> byte(0, 255);
  const int interesting_fc[] = {1, 2, 3, 4, 5, 6, 15, 16, 22, 23, 43, 17, 8, 0, 0x81, 255};
  const int interesting_unit[] = {0, 1, 2, 3, 255, 42};
  int fd = Connect(port);
  ASSERT_GE(fd, 0);
  int sent = 0, answered = 0, exception_codes = 0;
  for (int i = 0; i < 3000; ++i) {
    std::uint8_t frame[260];
    const int pdu_len = 1 + std::uniform_int_distribution<int>(0, 20)(rng);
    frame[0] = static_cast<std::uint8_t>(i >> 8);
    frame[1] = static_cast<std::uint8_t>(i);
    frame[2] = frame[3] = 0;
    frame[4] = 0;
    frame[5] = static_cast<std::uint8_t>(1 + pdu_len);
    frame[6] = static_cast<std::uint8_t>(interesting_unit[byte(rng) % 6]);
    frame[7] = static_cast<std::uint8_t>(interesting_fc[byte(rng) % 16]);
    for (int k = 1; k < pdu_len; ++k) frame[7 + k] = static_cast<std::uint8_t>(byte(rng) % 4 == 0 ? byte(rng) : byte(rng) % 24);
    if (i % 500 == 499) frame[2] = 7;  // now and then not MODBUS at all: the connection is dropped
    if (send(fd, frame, 7 + pdu_len, MSG_NOSIGNAL) < 0) {
      close(fd);
      fd = Connect(port);
      ASSERT_GE(fd, 0) << "terminal stopped accepting after " << i << " frames";
      continue;
    }
    ++sent;
    std::uint8_t reply[300];
    const ssize_t got = recv(fd, reply, sizeof reply, 0);
    if (got > 0) ++answered;
    if (frame[7] >= 0x80 && frame[2] == 0) {
      // An exception code as a request is not MODBUS: no reply that could look like an answer.
      ++exception_codes;
      EXPECT_LE(got, 0) << "function code " << int(frame[7]) << " was answered";
    }
    if (got <= 0) {  // dropped (or a request with no answer): reconnect
      close(fd);
      fd = Connect(port);
      ASSERT_GE(fd, 0) << "terminal stopped accepting after " << i << " frames";
    }
  }
  close(fd);
  EXPECT_GT(sent, 2500);
  // Every MODBUS-framed request is answered (normal or exception) within the
  // 1 s receive timeout; only the deliberately non-MODBUS frames are not.
  // (libmodbus' own refusal path sleeps and flushes; the terminal must not.)
  EXPECT_GT(exception_codes, 100);
  EXPECT_GE(answered, sent - 10 - exception_codes);

  // Invariants: the CNC never saw a compensation beyond the bound; read-only registers are intact.
  for (const auto& v : cnc.History())
    for (double c : v) EXPECT_LE(std::abs(c), 100.0 + 1e-9);
  ModbusCncLinkOptions lo;
  lo.endpoint.port = port;
  lo.endpoint.response_timeout_s = 1.0;
  ModbusCncLink link(lo);
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  ASSERT_TRUE(testing::WaitFor([&] { return link.Read(axes, state); })) << link.last_error();
  ASSERT_TRUE(link.WriteCompensation(std::vector<double>{1.0, 2.0, 3.0}));
  ASSERT_TRUE(testing::WaitFor([&] { return cnc.Compensation()[2] == 3.0; }));
  ModbusTemperatureSourceOptions to;
  to.endpoint.port = port;
  to.channel_names = {"a", "b", "c", "d", "e", "f", "g"};
  ModbusTemperatureSource rtd(to);  // checks module name 0x6015 and valid type codes on connect
  std::vector<hw::RawTemperature> t(7);
  ASSERT_TRUE(rtd.Read(t)) << rtd.last_error();
  EXPECT_GT(server->Stats().requests, 2000u);
}

}  // namespace
}  // namespace trueaxis::drivers
