#pragma once
// Five-axis kinematics (docs/fiveaxis.md): forward (joints → tool tip and
// tool axis in the workpiece frame) and inverse (tool tip + rotary angles →
// joints) for three families:
//
//   table A/C  tilting table, A about X carrying the C table — LinuxCNC xyzac-trt-kins
//   table B/C  tilting table, B about Y carrying the C table — LinuxCNC xyzbc-trt-kins
//   head B/C   spindle head, C about Z carrying the B tilt about Y (nutation-free fork head)
//
// Table families use LinuxCNC's parameters: the C axis passes through
// `pivot_mm` (x/y/z-rot-point), the tilt axis sits `offset_mm` from it
// (y-offset for A/C, x-offset for B/C, z-offset), and the tool length enters
// as LinuxCNC's tool-offset (added to the z offset). With
// `conventional_directions` the rotary axes turn as ISO 841 / RS274NGC say
// (LinuxCNC pin conventional-directions = 1, the values of its issue #2435);
// false gives LinuxCNC's historical default (both angles negated).
//
// Tool axis = unit vector from the tip towards the spindle. Joints are
// {X mm, Y mm, Z mm, tilt deg (A or B), rotary deg (C)}.
#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>

namespace trueaxis::fiveaxis {

enum class Family { kTableAC, kTableBC, kHeadBC };
std::string FamilyName(Family f);         // "table_ac", "table_bc", "head_bc"
std::optional<Family> ParseFamily(const std::string& name);

inline constexpr int kAxisCount = 5;
inline constexpr int kX = 0, kY = 1, kZ = 2, kTilt = 3, kRot = 4;
using AxisVector = std::array<double, kAxisCount>;
// "X","Y","Z" and "A"/"B", "C" for the family.
std::array<std::string, kAxisCount> AxisNames(Family f);

struct KinematicsParams {
  Family family = Family::kTableAC;
  Eigen::Vector3d pivot_mm = Eigen::Vector3d::Zero();   // tables: point on the C axis
  Eigen::Vector3d offset_mm = Eigen::Vector3d::Zero();  // tables: tilt axis relative to the C axis
  double tool_length_mm = 0;   // tables: LinuxCNC tool-offset; head: spindle nose → tip
  double pivot_length_mm = 0;  // head: B pivot → spindle nose along the tool axis
  bool conventional_directions = true;
};

struct ToolPose {
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();   // workpiece frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    // unit, tip → spindle, workpiece frame
};

class Kinematics {
 public:
  explicit Kinematics(KinematicsParams p) : p_(std::move(p)) {}
  const KinematicsParams& params() const { return p_; }

  ToolPose Forward(const AxisVector& joints) const;
  // Joints that put the tip at `tip_mm` with the rotary axes at tilt/rot (deg).
  AxisVector Inverse(const Eigen::Vector3d& tip_mm, double tilt_deg, double rot_deg) const;
  // Tool axis (workpiece frame) of the rotary angles.
  Eigen::Vector3d ToolAxis(double tilt_deg, double rot_deg) const;

  struct RotaryAngles {
    double tilt_deg = 0, rot_deg = 0;
    bool singular = false;  // tool axis parallel to the C axis: C is free, kept at previous
  };
  // Rotary angles giving tool axis `axis` (need not be unit), choosing of the
  // two solutions the one nearest `previous` (C unwrapped next to it). Within
  // `singular_tolerance_rad` of the C axis, C keeps its previous value.
  RotaryAngles AnglesFor(const Eigen::Vector3d& axis, const RotaryAngles& previous,
                         double singular_tolerance_rad = 1e-6) const;

 private:
  KinematicsParams p_;
};

// Angle (rad) between two tool axes.
double AxisAngleRad(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace trueaxis::fiveaxis
