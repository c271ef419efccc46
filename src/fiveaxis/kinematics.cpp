// Five-axis kinematics; equations in docs/fiveaxis.md (derived as rotation
// matrices; the table families reproduce LinuxCNC's trtfuncs equations).
#include "trueaxis/fiveaxis/kinematics.hpp"

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

namespace trueaxis::fiveaxis {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

Eigen::Matrix3d RotX(double rad) { return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d RotY(double rad) { return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d RotZ(double rad) { return Eigen::AngleAxisd(rad, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

}  // namespace

std::string FamilyName(Family f) {
  switch (f) {
    case Family::kTableAC: return "table_ac";
    case Family::kTableBC: return "table_bc";
    case Family::kHeadBC: return "head_bc";
  }
  return "?";
}

std::optional<Family> ParseFamily(const std::string& name) {
  for (Family f : {Family::kTableAC, Family::kTableBC, Family::kHeadBC})
    if (FamilyName(f) == name) return f;
  return std::nullopt;
}

std::array<std::string, kAxisCount> AxisNames(Family f) {
  return {"X", "Y", "Z", f == Family::kTableAC ? "A" : "B", "C"};
}

Eigen::Vector3d Kinematics::ToolAxis(double tilt_deg, double rot_deg) const {
  const double s = p_.conventional_directions ? 1.0 : -1.0;
  const double t = s * tilt_deg * kDegToRad, c = s * rot_deg * kDegToRad;
  const Eigen::Matrix3d tilt = p_.family == Family::kTableAC ? RotX(t) : RotY(t);
  return RotZ(c) * tilt * Eigen::Vector3d::UnitZ();
}

ToolPose Kinematics::Forward(const AxisVector& q) const {
  ToolPose pose;
  pose.axis = ToolAxis(q[kTilt], q[kRot]);
  const Eigen::Vector3d joints(q[kX], q[kY], q[kZ]);
  if (p_.family == Family::kHeadBC) {
    pose.tip_mm = joints - (p_.pivot_length_mm + p_.tool_length_mm) * pose.axis;
    return pose;
  }
  const double s = p_.conventional_directions ? 1.0 : -1.0;
  const double t = s * q[kTilt] * kDegToRad, c = s * q[kRot] * kDegToRad;
  const Eigen::Matrix3d tilt = p_.family == Family::kTableAC ? RotX(t) : RotY(t);
  const Eigen::Vector3d o = p_.offset_mm + Eigen::Vector3d(0, 0, p_.tool_length_mm);
  pose.tip_mm = RotZ(c) * (tilt * (joints - p_.pivot_mm - o) + o) + p_.pivot_mm;
  return pose;
}

AxisVector Kinematics::Inverse(const Eigen::Vector3d& tip_mm, double tilt_deg, double rot_deg) const {
  Eigen::Vector3d joints;
  if (p_.family == Family::kHeadBC) {
    joints = tip_mm + (p_.pivot_length_mm + p_.tool_length_mm) * ToolAxis(tilt_deg, rot_deg);
  } else {
    const double s = p_.conventional_directions ? 1.0 : -1.0;
    const double t = s * tilt_deg * kDegToRad, c = s * rot_deg * kDegToRad;
    const Eigen::Matrix3d tilt_inverse = p_.family == Family::kTableAC ? RotX(-t) : RotY(-t);
    const Eigen::Vector3d o = p_.offset_mm + Eigen::Vector3d(0, 0, p_.tool_length_mm);
    joints = tilt_inverse * (RotZ(-c) * (tip_mm - p_.pivot_mm) - o) + o + p_.pivot_mm;
  }
  return {joints.x(), joints.y(), joints.z(), tilt_deg, rot_deg};
}

Kinematics::RotaryAngles Kinematics::AnglesFor(const Eigen::Vector3d& axis_in, const RotaryAngles& previous,
                                               double singular_tolerance_rad) const {
  const Eigen::Vector3d a = axis_in.normalized();
  const double s = p_.conventional_directions ? 1.0 : -1.0;
  // Effective (conventional) angles: A/C: axis = (sin c sin t, −cos c sin t, cos t);
  // B/C: axis = (cos c sin t, sin c sin t, cos t).
  const double t_eff = std::acos(std::clamp(a.z(), -1.0, 1.0));
  const double c_eff = p_.family == Family::kTableAC ? std::atan2(a.x(), -a.y()) : std::atan2(a.y(), a.x());
  const bool singular = std::sin(t_eff) < singular_tolerance_rad;
  auto unwrap = [&](double rot_deg) { return rot_deg + 360.0 * std::round((previous.rot_deg - rot_deg) / 360.0); };
  RotaryAngles best;
  double best_distance = INFINITY;
  for (int branch = 0; branch < 2; ++branch) {
    RotaryAngles cand;
    cand.singular = singular;
    cand.tilt_deg = s * (branch == 0 ? t_eff : -t_eff) / kDegToRad;
    cand.rot_deg = singular ? previous.rot_deg : unwrap(s * (c_eff + (branch == 0 ? 0 : std::numbers::pi)) / kDegToRad);
    const double distance = std::abs(cand.tilt_deg - previous.tilt_deg) + std::abs(cand.rot_deg - previous.rot_deg);
    if (distance < best_distance) best_distance = distance, best = cand;
  }
  return best;
}

double AxisAngleRad(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // atan2 of |a×b| and a·b: accurate for the micro-radian angles compared here.
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace trueaxis::fiveaxis
