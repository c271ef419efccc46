// Feed hold on the virtual machine (seed 001's stop rule): motion programs wait in place while
// held, time and heat go on, and releasing resumes them where they stopped.
#include <gtest/gtest.h>

#include "sim_test_util.hpp"
#include "trueaxis/sim/virtual_machine.hpp"

namespace trueaxis::sim {
namespace {
using testing::TestMachine;

TEST(FeedHold, StopsMotionProgramsAndResumesThem) {
  VirtualMachine vm(TestMachine(), 3);
  vm.CommandMove(0, 400, 1200);  // 20 mm/s
  vm.Advance(5);
  const double at_hold = vm.CommandedMm(0);
  EXPECT_NEAR(at_hold, 100, 1e-6);
  vm.SetFeedHold(true);
  EXPECT_TRUE(vm.FeedHold());
  vm.Advance(30);
  EXPECT_DOUBLE_EQ(vm.CommandedMm(0), at_hold);
  EXPECT_EQ(vm.FeedNowMmMin(0), 0.0);
  EXPECT_NEAR(vm.TimeS(), 35, 1e-9);  // the clock goes on
  hw::AxisState st[2];
  hw::CncState ms;
  ASSERT_TRUE(vm.Read(st, ms));
  EXPECT_FALSE(st[0].moving);
  EXPECT_THROW(vm.MoveTo(1, 10, 1000), std::logic_error);  // would never arrive
  vm.SetFeedHold(false);
  vm.Advance(5);
  EXPECT_NEAR(vm.CommandedMm(0), 200, 1e-6);  // resumed where it stopped
}

TEST(FeedHold, HoldsAReciprocatingAxis) {
  VirtualMachine vm(TestMachine(), 4);
  vm.CommandReciprocate(0, 0, 300, 3000);
  vm.Advance(2);
  vm.SetFeedHold(true);
  const double p = vm.CommandedMm(0);
  for (int i = 0; i < 10; ++i) {
    vm.Advance(7);
    EXPECT_DOUBLE_EQ(vm.CommandedMm(0), p);
  }
}

}  // namespace
}  // namespace trueaxis::sim
