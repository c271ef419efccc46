// One MODBUS transaction per cycle where the terminal allows it: FC 23 (read/write multiple
// registers) writes the command block and reads the PMC window's copy in holding registers 100….
// ModbusCncLink::WriteAndRead uses it, an independent peer (pymodbus) sees the same copy, and an
// older terminal that refuses FC 23 is asked with FC 16 + FC 04 instead.
#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "modbus_test_server.hpp"
#include "peers/pymodbus_peer.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/terminal_registers.hpp"

namespace trueaxis::drivers {
namespace {

using testing::MockCnc;
using testing::MockTemperatures;
using testing::StartServer;
using testing::WaitFor;

ModbusCncLinkOptions LinkTo(int port) {
  ModbusCncLinkOptions o;
  o.endpoint.port = port;
  o.endpoint.response_timeout_s = 1.0;
  return o;
}

TEST(ReadWrite, OneTransactionWritesTheCommandAndReadsTheWindow) {
  MockCnc cnc({"X", "Y", "Z"});
  MockTemperatures temps(2);
  cnc.SetAxis(0, {-81.2345, -1, true});
  cnc.SetState({CoolantState::kFlood, true});
  std::string error;
  auto server = StartServer(&cnc, &temps, {}, &error);
  ASSERT_NE(server, nullptr) << error;
  ModbusCncLink link(LinkTo(server->options().port));
  ASSERT_TRUE(link.Connect()) << link.last_error();
  std::vector<hw::AxisState> axes(3);
  hw::CncState machine;
  const std::vector<double> command = {-7.5, 0.3, 120.0};
  const auto before = server->Stats().requests;
  ASSERT_TRUE(link.WriteAndRead(command, axes, machine)) << link.last_error();
  EXPECT_EQ(server->Stats().requests, before + 1);  // one transaction for the write and the read
  EXPECT_TRUE(link.read_write_answered());
  EXPECT_NEAR(axes[0].position_mm, -81.2345, 0.5e-4);
  EXPECT_EQ(axes[0].servo_direction, -1);
  EXPECT_TRUE(axes[0].moving);
  EXPECT_EQ(machine.coolant, CoolantState::kFlood);
  ASSERT_TRUE(WaitFor([&] { return std::abs(cnc.Compensation()[2] - 120.0) < 1e-9; }));
  EXPECT_NEAR(cnc.Compensation()[0], -7.5, 1e-9);
  // the next cycle's read part shows what the CNC applies
  ASSERT_TRUE(WaitFor([&] { return link.WriteAndRead(command, axes, machine) && link.applied_um()[0] == -7.5; }));
  EXPECT_NEAR(link.applied_um()[2], 120.0, 1e-9);
  // beyond the terminal's bound: refused as FC 16 is (0x03), nothing applied, FC 23 still in use
  EXPECT_FALSE(link.WriteAndRead(std::vector<double>{5000.0, 0, 0}, axes, machine));
  EXPECT_NEAR(cnc.Compensation()[0], -7.5, 1e-9);
  ASSERT_TRUE(link.WriteAndRead(command, axes, machine)) << link.last_error();
  EXPECT_TRUE(link.read_write_answered());
}

TEST(ReadWrite, PymodbusSeesTheWindowCopyThroughFc23) {
  MockCnc cnc({"X", "Y"});
  MockTemperatures temps(1);
  cnc.SetAxis(1, {333.0001, +1, false});
  cnc.SetState({CoolantState::kAir, true});
  std::string error;
  auto server = StartServer(&cnc, &temps, {}, &error);
  ASSERT_NE(server, nullptr) << error;
  const nlohmann::json j =
      trueaxis::testing::RunPymodbusPeer("--read-write " + std::to_string(server->options().port) + " 2 -0.4 25.5");
  ASSERT_FALSE(j.contains("error")) << j.dump();
  const auto copy = j["copy"].get<std::vector<int>>(), window = j["window"].get<std::vector<int>>();
  ASSERT_EQ(copy.size(), static_cast<std::size_t>(pmc::InputWindowLength(2)));
  ASSERT_EQ(window.size(), copy.size());
  EXPECT_EQ(copy[pmc::kIrLayoutVersion], 1);
  EXPECT_EQ(copy[pmc::kIrAxisCount], 2);
  EXPECT_EQ(copy[pmc::kIrCoolant], 3);
  // the machine's state is the same in the copy and in the window (the heartbeat, age, status
  // and applied values move between the two reads)
  for (std::size_t a = 0; a < 2; ++a)
    for (int f : {pmc::kIrAxisPositionHi, pmc::kIrAxisPositionLo, pmc::kIrAxisDirection, pmc::kIrAxisMoving})
      EXPECT_EQ(copy[pmc::InputAxisRegister(a, f)], window[pmc::InputAxisRegister(a, f)]) << a << " " << f;
  const std::int32_t y = static_cast<std::int32_t>((static_cast<std::uint32_t>(copy[pmc::InputAxisRegister(1, 0)]) << 16) |
                                                   static_cast<std::uint32_t>(copy[pmc::InputAxisRegister(1, 1)]));
  EXPECT_EQ(y, 3330001);
  ASSERT_TRUE(WaitFor([&] { return std::abs(cnc.Compensation()[1] - 25.5) < 1e-9; }));
  EXPECT_NEAR(cnc.Compensation()[0], -0.4, 1e-9);
}

// A terminal of layout 1 without FC 23 (and without the window's copy): libmodbus answering
// FC 04/03/16 from a map laid out by the register model, refusing FC 23 with 0x01.
class OlderTerminal {
 public:
  explicit OlderTerminal(std::size_t axes) : axes_(axes) {
    std::uint16_t ir[pmc::kInputRegisterCount], hr[pmc::kHoldingImageCount];
    InitPmcImage(ir, hr, axes, true);
    std::vector<hw::AxisState> state(axes);
    state[0].position_mm = 12.5;
    const std::vector<double> travel(axes, 0.0);
    EncodePmcState({7, true, true, {CoolantState::kOff, true}, state, travel, 0}, ir, hr);
    map_ = modbus_mapping_new(0, 0, PmcHoldingLength(axes), pmc::InputWindowLength(axes));
    std::copy(ir, ir + pmc::InputWindowLength(axes), map_->tab_input_registers);
    std::copy(hr, hr + PmcHoldingLength(axes), map_->tab_registers);
    std::mt19937 rng(std::random_device{}());
    for (int attempt = 0; attempt < 50 && listen_fd_ < 0; ++attempt) {
      port_ = 20000 + static_cast<int>(rng() % 40000);
      if (ctx_) modbus_free(ctx_);
      ctx_ = modbus_new_tcp("127.0.0.1", port_);
      listen_fd_ = modbus_tcp_listen(ctx_, 1);
    }
    thread_ = std::thread([this] { Serve(); });
  }
  ~OlderTerminal() {
    stop_ = true;
    shutdown(listen_fd_, SHUT_RDWR);
    thread_.join();
    close(listen_fd_);
    modbus_free(ctx_);
    modbus_mapping_free(map_);
  }
  int port() const { return port_; }
  int read_write_refused() const { return refused_.load(); }
  double CommandUm(std::size_t axis) const {
    std::vector<double> c(axes_);
    DecodeCommand(map_->tab_registers + pmc::kHrCompensationBase, c);
    return c[axis];
  }

 private:
  void Serve() {
    while (!stop_) {
      int fd = listen_fd_;
      if (modbus_tcp_accept(ctx_, &fd) < 0) return;
      std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
      for (;;) {
        const int rc = modbus_receive(ctx_, query);
        if (rc <= 0) break;
        if (query[7] == MODBUS_FC_WRITE_AND_READ_REGISTERS) {
          ++refused_;
          modbus_reply_exception(ctx_, query, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
        } else {
          modbus_reply(ctx_, query, rc, map_);
        }
      }
      close(fd);
    }
  }
  std::size_t axes_;
  modbus_t* ctx_ = nullptr;
  modbus_mapping_t* map_ = nullptr;
  int listen_fd_ = -1, port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> refused_{0};
  std::thread thread_;
};

TEST(ReadWrite, AnOlderTerminalWithoutFc23GetsFc16AndFc04) {
  OlderTerminal terminal(3);
  ModbusCncLink link(LinkTo(terminal.port()));
  ASSERT_TRUE(link.Connect()) << link.last_error();
  std::vector<hw::AxisState> axes(3);
  hw::CncState machine;
  ASSERT_TRUE(link.WriteAndRead(std::vector<double>{4.2, -1.0, 0.0}, axes, machine)) << link.last_error();
  EXPECT_FALSE(link.read_write_answered());
  EXPECT_EQ(terminal.read_write_refused(), 1);
  EXPECT_NEAR(terminal.CommandUm(0), 4.2, 1e-9);
  EXPECT_NEAR(terminal.CommandUm(1), -1.0, 1e-9);
  EXPECT_NEAR(axes[0].position_mm, 12.5, 1e-9);
  // asked once: the next cycles go straight to FC 16 + FC 04
  ASSERT_TRUE(link.WriteAndRead(std::vector<double>{4.3, -1.0, 0.0}, axes, machine)) << link.last_error();
  EXPECT_EQ(terminal.read_write_refused(), 1);
  EXPECT_NEAR(terminal.CommandUm(0), 4.3, 1e-9);
}

}  // namespace
}  // namespace trueaxis::drivers
