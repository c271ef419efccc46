// Kinematics: hand-worked poses, LinuxCNC's published inverse cases, round trips, singular orientation.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "trueaxis/fiveaxis/kinematics.hpp"

namespace trueaxis::fiveaxis {
namespace {

void ExpectJoints(const AxisVector& q, double x, double y, double z) {
  EXPECT_NEAR(q[kX], x, 1e-9);
  EXPECT_NEAR(q[kY], y, 1e-9);
  EXPECT_NEAR(q[kZ], z, 1e-9);
}

// LinuxCNC issue #2435: xyzbc-trt inverse with conventional directions.
TEST(FiveAxisKinematics, LinuxCncIssue2435TableBCCases) {
  KinematicsParams p;
  p.family = Family::kTableBC;
  const Kinematics kin(p);
  ExpectJoints(kin.Inverse({1, 0, 2}, 0, 0), 1, 0, 2);
  ExpectJoints(kin.Inverse({1, 0, 2}, 90, 0), -2, 0, 1);
  ExpectJoints(kin.Inverse({1, 0, 2}, 0, 90), 0, -1, 2);
}

// xyzac-trt's equations (trtfuncs_math.h) worked by hand, conventional
// directions, zero pivot: (1, 0, 2) at A = 90 → joints (1, 2, 0); at C = 90 → (0, −1, 2).
TEST(FiveAxisKinematics, LinuxCncTableACCasesByHand) {
  KinematicsParams p;
  p.family = Family::kTableAC;
  const Kinematics kin(p);
  ExpectJoints(kin.Inverse({1, 0, 2}, 90, 0), 1, 2, 0);
  ExpectJoints(kin.Inverse({1, 0, 2}, 0, 90), 0, -1, 2);
  // With LinuxCNC's y/z offsets and tool offset: the tilt axis at (y, z) = (5, 40 + 10).
  p.offset_mm = {0, 5, 40};
  p.tool_length_mm = 10;
  const Kinematics with_offsets(p);
  ExpectJoints(with_offsets.Inverse({0, 5, 60}, 90, 0), 0, 15, 50);
}

// LinuxCNC's historical (unconventional) directions negate both angles.
TEST(FiveAxisKinematics, UnconventionalDirectionsNegateTheAngles) {
  KinematicsParams p;
  p.family = Family::kTableBC;
  p.conventional_directions = false;
  const Kinematics kin(p);
  ExpectJoints(kin.Inverse({1, 0, 2}, -90, 0), -2, 0, 1);
  ExpectJoints(kin.Inverse({1, 0, 2}, 0, -90), 0, -1, 2);
}

// Hand-worked table A/C pose with pivot and offsets: A = 90° turns the
// workpiece point about the tilt axis (through pivot + offset, along X).
TEST(FiveAxisKinematics, TableACHandWorkedPose) {
  KinematicsParams p;
  p.family = Family::kTableAC;
  p.pivot_mm = {10, 20, 30};
  p.offset_mm = {0, 5, 40};
  p.tool_length_mm = 0;
  const Kinematics kin(p);
  // Workpiece point at the tilt axis's Y, 10 mm above it: after A = 90 the
  // machine sees it 10 mm towards −Y... per R_x(−90): (y, z) → (z, −y).
  // Tilt axis at y = 25, z = 70. Point (10, 25, 80): relative (0, 0, 10) → (0, 10, 0).
  ExpectJoints(kin.Inverse({10, 25, 80}, 90, 0), 10, 35, 70);
  // C = 90 about the C axis through (10, 20): workpiece (20, 20, 30) → machine (10, 10, 30).
  ExpectJoints(kin.Inverse({20, 20, 30}, 0, 90), 10, 10, 30);
  // Tool axis: A tilts it towards −Y of the workpiece, C then turns that about Z.
  const Eigen::Vector3d axis = kin.ToolAxis(30, 90);
  EXPECT_NEAR(axis.x(), std::sin(30 * M_PI / 180), 1e-12);
  EXPECT_NEAR(axis.y(), 0, 1e-12);
  EXPECT_NEAR(axis.z(), std::cos(30 * M_PI / 180), 1e-12);
}

// Head B/C: the pivot sits (pivot length + tool length) up the tool axis.
TEST(FiveAxisKinematics, HeadBCHandWorkedPose) {
  KinematicsParams p;
  p.family = Family::kHeadBC;
  p.pivot_length_mm = 150;
  p.tool_length_mm = 50;
  const Kinematics kin(p);
  ExpectJoints(kin.Inverse({0, 0, 0}, 0, 0), 0, 0, 200);
  ExpectJoints(kin.Inverse({0, 0, 0}, 90, 0), 200, 0, 0);   // B = 90: axis along +X
  ExpectJoints(kin.Inverse({1, 2, 3}, 90, 90), 1, 202, 3);  // C = 90 turns it to +Y
  const ToolPose pose = kin.Forward({200, 0, 0, 90, 0});
  EXPECT_NEAR(pose.tip_mm.norm(), 0, 1e-9);
}

TEST(FiveAxisKinematics, RoundTripsForEveryFamily) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-300, 300), ang(-110, 110), c(-400, 400), par(-80, 80);
  for (Family f : {Family::kTableAC, Family::kTableBC, Family::kHeadBC}) {
    for (bool conventional : {true, false}) {
      if (f == Family::kHeadBC && !conventional) continue;
      KinematicsParams p;
      p.family = f;
      p.conventional_directions = conventional;
      p.tool_length_mm = 75;
      if (f == Family::kHeadBC) p.pivot_length_mm = 120;
      else p.pivot_mm = {par(rng), par(rng), par(rng)}, p.offset_mm = {par(rng), par(rng), par(rng)};
      const Kinematics kin(p);
      for (int i = 0; i < 200; ++i) {
        const Eigen::Vector3d tip(pos(rng), pos(rng), pos(rng));
        const double t = ang(rng), r = c(rng);
        const AxisVector q = kin.Inverse(tip, t, r);
        const ToolPose back = kin.Forward(q);
        EXPECT_LT((back.tip_mm - tip).norm(), 1e-9) << FamilyName(f);
        EXPECT_LT(AxisAngleRad(back.axis, kin.ToolAxis(t, r)), 1e-12);
        // Angles from the axis: the same axis again, nearest the angles given as previous.
        const auto angles = kin.AnglesFor(back.axis, {t + 0.3, r - 0.3, false});
        EXPECT_NEAR(angles.tilt_deg, t, 1e-6) << FamilyName(f);
        EXPECT_NEAR(angles.rot_deg, r, 1e-6) << FamilyName(f);
      }
    }
  }
}

// Tool axis parallel to the C axis: C is free; it keeps its previous value
// and the pose is still exact.
TEST(FiveAxisKinematics, SingularOrientationKeepsTheRotaryAxis) {
  for (Family f : {Family::kTableAC, Family::kHeadBC}) {
    KinematicsParams p;
    p.family = f;
    const Kinematics kin(p);
    const auto angles = kin.AnglesFor(Eigen::Vector3d::UnitZ(), {3.0, 123.0, false});
    EXPECT_TRUE(angles.singular);
    EXPECT_NEAR(angles.tilt_deg, 0, 1e-9);
    EXPECT_DOUBLE_EQ(angles.rot_deg, 123.0);
    // Whatever C, the axis at tilt 0 is +Z and the tip is where it should be.
    const Eigen::Vector3d tip(5, -7, 9);
    for (double c : {0.0, 45.0, 123.0}) {
      const ToolPose pose = kin.Forward(kin.Inverse(tip, 0, c));
      EXPECT_LT((pose.tip_mm - tip).norm(), 1e-9);
      EXPECT_LT(AxisAngleRad(pose.axis, Eigen::Vector3d::UnitZ()), 1e-12);
    }
  }
}

}  // namespace
}  // namespace trueaxis::fiveaxis
