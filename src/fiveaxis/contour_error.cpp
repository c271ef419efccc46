// Contour error by forward kinematics and a tracked nearest-point search.
#include "trueaxis/fiveaxis/contour_error.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace trueaxis::fiveaxis {

NearestPointTracker::NearestPointTracker(const ToolPath& path, const Kinematics& kin) : kin_(kin) {
  double s = 0;
  for (std::size_t i = 0; i < path.vertices.size(); ++i) {
    const auto& v = path.vertices[i];
    if (i > 0) s += (v.tip_mm - tip_.back()).norm();
    tip_.push_back(v.tip_mm);
    tilt_.push_back(v.tilt_deg);
    rot_.push_back(v.rot_deg);
    arc_.push_back(s);
  }
  previous_tip_ = tip_.front();
}

NearestPointTracker::Match NearestPointTracker::Next(const ToolPose& pose) {
  const double travel = first_ ? 0.0 : (pose.tip_mm - previous_tip_).norm();
  const double window = std::max(1.0, 4 * previous_distance_ + 4 * travel);
  // The first sample is matched near the path's start (a closed path ends
  // where it starts), within 4× its distance from the start.
  const double start_window = std::max(1.0, 4 * (pose.tip_mm - tip_.front()).norm());
  const double lo = first_ ? -1.0 : previous_arc_ - window, hi = first_ ? start_window : previous_arc_ + window;
  // Segments whose arc range meets [lo, hi].
  std::size_t begin = std::upper_bound(arc_.begin(), arc_.end(), lo) - arc_.begin();
  begin = std::max<std::size_t>(1, begin == 0 ? 1 : begin);
  Match best;
  best.distance_mm = INFINITY;
  for (std::size_t k = begin; k < tip_.size() && arc_[k - 1] <= hi; ++k) {
    const Eigen::Vector3d d = tip_[k] - tip_[k - 1];
    const double len2 = d.squaredNorm();
    auto axis_at = [&](double f) {
      return kin_.ToolAxis(tilt_[k - 1] + f * (tilt_[k] - tilt_[k - 1]), rot_[k - 1] + f * (rot_[k] - rot_[k - 1]));
    };
    double f;
    if (len2 > 1e-18) {
      f = std::clamp((pose.tip_mm - tip_[k - 1]).dot(d) / len2, 0.0, 1.0);
    } else {
      // Tip standing: the fraction whose tool axis is nearest (coarse then fine).
      f = 0;
      double best_angle = INFINITY;
      for (int pass = 0, steps = 16; pass < 2; ++pass) {
        const double centre = f, span = pass == 0 ? 0.5 : 1.0 / steps;
        for (int i = 0; i <= steps; ++i) {
          const double g = std::clamp(centre - span + 2 * span * i / steps, 0.0, 1.0);
          const double a = AxisAngleRad(axis_at(g), pose.axis);
          if (a < best_angle) best_angle = a, f = g;
        }
      }
    }
    const double dist = (pose.tip_mm - (tip_[k - 1] + f * d)).norm();
    const double angle = AxisAngleRad(axis_at(f), pose.axis);
    // Ties (a corner vertex shared by two segments, a standing tip) go to the better orientation.
    if (dist < best.distance_mm - 1e-9 || (dist < best.distance_mm + 1e-9 && angle < best.angle_rad)) {
      best.distance_mm = dist;
      best.angle_rad = angle;
      best.segment = k;
      best.fraction = f;
      best.arc_mm = arc_[k - 1] + f * (arc_[k] - arc_[k - 1]);
    }
  }
  first_ = false;
  previous_arc_ = best.arc_mm;
  previous_distance_ = best.distance_mm;
  previous_tip_ = pose.tip_mm;
  return best;
}

ContourErrors EvaluateContour(const ToolPath& path, const Kinematics& kin, const std::vector<AxisVector>& actual) {
  ContourErrors out;
  NearestPointTracker tracker(path, kin);
  double sum2 = 0, sum2_angle = 0;
  for (const AxisVector& q : actual) {
    const auto m = tracker.Next(kin.Forward(q));
    out.position_um.push_back(m.distance_mm * 1e3);
    out.orientation_urad.push_back(m.angle_rad * 1e6);
    out.path_mm.push_back(m.arc_mm);
    sum2 += out.position_um.back() * out.position_um.back();
    sum2_angle += out.orientation_urad.back() * out.orientation_urad.back();
    out.max_um = std::max(out.max_um, out.position_um.back());
    out.max_urad = std::max(out.max_urad, out.orientation_urad.back());
  }
  if (!actual.empty()) {
    out.rms_um = std::sqrt(sum2 / actual.size());
    out.rms_urad = std::sqrt(sum2_angle / actual.size());
    const PathVertex& end = path.vertices.back();
    const ToolPose at_end = kin.Forward(actual.back());
    out.end_point_um = (at_end.tip_mm - end.tip_mm).norm() * 1e3;
    const Eigen::Vector3d end_axis = kin.ToolAxis(end.tilt_deg, end.rot_deg);
    out.end_orientation_urad = std::atan2(at_end.axis.cross(end_axis).norm(), at_end.axis.dot(end_axis)) * 1e6;
  }
  return out;
}

}  // namespace trueaxis::fiveaxis
