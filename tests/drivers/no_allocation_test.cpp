// The clients' contract: no allocation per call once connected (they run in
// the compensator's cycle). malloc/calloc/realloc are interposed for this
// test program and counted per thread while a test asks for it; every C++
// `new` and every allocation inside libmodbus goes through them.
#include <gtest/gtest.h>

#include <cstddef>
#include <memory>
#include <vector>

#include "modbus_test_server.hpp"
#include "trueaxis/drivers/modbus_cnc_link.hpp"
#include "trueaxis/drivers/modbus_temperature_source.hpp"

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
}

namespace {
thread_local bool g_counting = false;
thread_local long g_allocations = 0;
}  // namespace

extern "C" void* malloc(std::size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t n, std::size_t m) {
  if (g_counting) ++g_allocations;
  return __libc_calloc(n, m);
}
extern "C" void* realloc(void* p, std::size_t n) {
  if (g_counting) ++g_allocations;
  return __libc_realloc(p, n);
}

namespace trueaxis::drivers {
namespace {

TEST(NoAllocation, TheCounterSeesAllocations) {  // so a 0 below means something
  g_allocations = 0;
  g_counting = true;
  auto v = std::make_unique<std::vector<int>>(100);
  g_counting = false;
  EXPECT_GE(g_allocations, 2);
}

TEST(NoAllocation, ClientsReadAndWriteWithoutAllocatingOnceConnected) {
  testing::MockCnc cnc({"X", "Y", "Z"});
  testing::MockTemperatures temps(9);
  std::string error;
  auto server = testing::StartServer(&cnc, &temps, {}, &error);
  ASSERT_NE(server, nullptr) << error;
  ModbusCncLinkOptions lo;
  lo.endpoint.port = server->options().port;
  lo.endpoint.response_timeout_s = 1.0;  // shared, loaded build machine: success is what is tested
  ModbusCncLink link(lo);
  ModbusTemperatureSourceOptions to;
  to.endpoint.port = server->options().port;
  to.endpoint.response_timeout_s = 1.0;
  to.unit_ids = {2, 3};
  for (int i = 0; i < 9; ++i) to.channel_names.push_back("t" + std::to_string(i));
  ModbusTemperatureSource source(to);
  std::vector<hw::AxisState> axes(3);
  hw::CncState state;
  std::vector<hw::RawTemperature> t(9);
  std::vector<double> corr = {1.0, -2.0, 3.0};
  ASSERT_TRUE(link.Read(axes, state)) << link.last_error();  // connects, handshakes
  ASSERT_TRUE(source.Read(t)) << source.last_error();
  int ok = 0;
  g_allocations = 0;
  g_counting = true;
  for (int i = 0; i < 200; ++i) {
    corr[0] = 0.1 * i;
    ok += link.Read(axes, state);
    ok += link.WriteCompensation(corr);
    ok += source.Read(t);
  }
  g_counting = false;
  EXPECT_EQ(ok, 600);
  EXPECT_EQ(g_allocations, 0);

  // A module that stays down fails every cycle; after the first failure
  // (which formats the message) the repeats allocate nothing either.
  temps.SetOk(false);
  // The server's own thread takes the modules offline: a read in flight then can still pass its
  // registers and fail at the coils (another message). Wait until the reads fail as they will from
  // now on, at the first request.
  ASSERT_TRUE(testing::WaitFor(
      [&] { return !source.Read(t) && source.last_error().find("read holding registers") != std::string::npos; }));
  g_allocations = 0;
  g_counting = true;
  int failed = 0;
  for (int i = 0; i < 50; ++i) failed += !source.Read(t);
  g_counting = false;
  EXPECT_EQ(failed, 50);
  EXPECT_EQ(g_allocations, 0);
  EXPECT_NE(source.last_error().find("Target device failed to respond"), std::string::npos) << source.last_error();
}

}  // namespace
}  // namespace trueaxis::drivers
