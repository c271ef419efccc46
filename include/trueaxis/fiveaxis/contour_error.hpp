#pragma once
// Contour (linkage) error, seed 004: the actual tool pose from the forward
// kinematics of the actual joints, against the nearest point of the
// commanded tool path (docs/fiveaxis.md, "Contour error"). The position part
// is the distance of the actual tip from the path polyline; the orientation
// part the angle between the actual tool axis and the commanded one at that
// nearest point. The nearest point is tracked along the path: each sample
// searches the segments within a window around the previous one (wide enough
// for twice the error plus the travel), so a path that closes on itself or
// passes near an earlier part is not mistaken, and a sharp corner — where the
// nearest point sits at the vertex while the tool rounds it — is exact.
// Segments where only the rotary axes move (tip standing) are matched by
// orientation.
#include <vector>

#include "trueaxis/fiveaxis/tool_path.hpp"

namespace trueaxis::fiveaxis {

struct ContourErrors {
  std::vector<double> position_um;     // per sample
  std::vector<double> orientation_urad;
  std::vector<double> path_mm;         // arc length of the nearest point
  double rms_um = 0, max_um = 0, rms_urad = 0, max_urad = 0;
  // The last sample's tip and tool axis against the path's last vertex: how
  // far off the programmed end point the run stands (a contour error measures
  // distance from the path, not where along it the run ends).
  double end_point_um = 0, end_orientation_urad = 0;
};

class NearestPointTracker {
 public:
  NearestPointTracker(const ToolPath& path, const Kinematics& kin);
  struct Match {
    double distance_mm = 0, angle_rad = 0, arc_mm = 0;
    std::size_t segment = 0;  // v[segment-1] → v[segment]
    double fraction = 0;
  };
  // The nearest path point of pose, searched around the previous match.
  Match Next(const ToolPose& pose);
  double length_mm() const { return arc_.back(); }

 private:
  std::vector<Eigen::Vector3d> tip_;
  std::vector<double> tilt_, rot_, arc_;
  const Kinematics& kin_;
  double previous_arc_ = 0, previous_distance_ = 0;
  Eigen::Vector3d previous_tip_;
  bool first_ = true;
};

ContourErrors EvaluateContour(const ToolPath& path, const Kinematics& kin, const std::vector<AxisVector>& actual);

}  // namespace trueaxis::fiveaxis
