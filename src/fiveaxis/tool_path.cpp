// Built-in five-axis test paths and rotary range checks.
#include "trueaxis/fiveaxis/tool_path.hpp"

#include <cmath>
#include <functional>
#include <numbers>

#include <Eigen/Geometry>
#include <fmt/format.h>

#include "trueaxis/core/input_error.hpp"

namespace trueaxis::fiveaxis {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// A feed move to `tip` with the rotary angles `angles` (the first vertex is the start).
void AddFeedVertex(ToolPath& path, const Eigen::Vector3d& tip, const Kinematics::RotaryAngles& angles, double feed) {
  PathVertex v;
  v.tip_mm = tip;
  v.tilt_deg = angles.tilt_deg;
  v.rot_deg = angles.rot_deg;
  v.move = path.vertices.empty() ? MoveKind::kStart : MoveKind::kFeed;
  v.feed_mm_per_min = feed;
  path.vertices.push_back(v);
}

// Samples tip(u), axis(u) for u in [0, 1] every ~0.05 mm of tip travel.
ToolPath Sample(const std::string& name, const Kinematics& kin, double feed_mm_per_min, double length_mm,
                const std::function<void(double, Eigen::Vector3d&, Eigen::Vector3d&)>& at) {
  ToolPath path;
  path.name = name;
  const int n = std::max(200, static_cast<int>(std::ceil(length_mm / 0.05)));
  Kinematics::RotaryAngles prev;
  for (int i = 0; i <= n; ++i) {
    Eigen::Vector3d tip, axis;
    at(static_cast<double>(i) / n, tip, axis);
    prev = kin.AnglesFor(axis, prev);
    AddFeedVertex(path, tip, prev, feed_mm_per_min);
  }
  return path;
}

}  // namespace

std::vector<std::string> TestPathNames() { return {"cone", "s-shape", "inclined-circle", "helix", "inclined-pocket"}; }

ToolPath MakeTestPath(const std::string& name, const Kinematics& kin, double feed) {
  if (name == "cone") {
    // NAS 979 / ISO 10791-7 cone frustum: half-angle 15°, cone axis inclined
    // 10° about X; the tool flanks the cone along its generatrix while its tip
    // runs a Ø100 mm circle (one turn) 20 mm above the table.
    const double half = 15 * kDeg, radius = 50;
    const Eigen::Matrix3d incline = Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Vector3d u1 = incline * Eigen::Vector3d::UnitX(), u2 = incline * Eigen::Vector3d::UnitY(),
                          w = incline * Eigen::Vector3d::UnitZ();
    return Sample(name, kin, feed, 2 * kPi * radius, [&](double u, Eigen::Vector3d& tip, Eigen::Vector3d& axis) {
      const double phi = 2 * kPi * u;
      const Eigen::Vector3d radial = std::cos(phi) * u1 + std::sin(phi) * u2;
      tip = Eigen::Vector3d(0, 0, 20) + radius * radial;
      axis = (w - std::tan(half) * radial).normalized();
    });
  }
  if (name == "s-shape") {
    // S-shaped ruled surface (in the spirit of ISO 10791-7:2020's S test
    // piece): the tip follows a bottom S curve over 160 mm, the tool axis the
    // ruling to a top curve 40 mm higher, tilting between about −20° and +35°.
    const double length = 160, amplitude = 25, height = 40;
    auto bottom = [&](double x) { return Eigen::Vector3d(x, amplitude * std::sin(2 * kPi * x / length), 0); };
    auto top = [&](double x) {
      return Eigen::Vector3d(x, 0.4 * amplitude * std::sin(2 * kPi * x / length) + 12 * std::cos(kPi * x / length),
                             height);
    };
    return Sample(name, kin, feed, 230, [&](double u, Eigen::Vector3d& tip, Eigen::Vector3d& axis) {
      const double x = -length / 2 + length * u;
      tip = bottom(x);
      axis = (top(x) - bottom(x)).normalized();
    });
  }
  if (name == "inclined-circle") {
    // Ø80 mm circle in a plane inclined 30° about X, tool normal to the plane:
    // the rotary axes stand still, the linear axes run the circle.
    const double radius = 40;
    const Eigen::Matrix3d incline = Eigen::AngleAxisd(30 * kDeg, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return Sample(name, kin, feed, 2 * kPi * radius, [&](double u, Eigen::Vector3d& tip, Eigen::Vector3d& axis) {
      const double phi = 2 * kPi * u;
      tip = Eigen::Vector3d(0, 0, 10) + incline * Eigen::Vector3d(radius * std::cos(phi), radius * std::sin(phi), 0);
      axis = incline * Eigen::Vector3d::UnitZ();
    });
  }
  if (name == "helix") {
    // Three turns of a Ø60 mm helix descending 15 mm (helical entry), the
    // tool leaning 20° outwards: the rotary axis turns 1080° at constant speed
    // while the tilt holds — long, winding, with no rest to settle in.
    const double radius = 30, turns = 3, drop = 15, lean = 20 * kDeg;
    const double length = std::hypot(2 * kPi * radius * turns, drop);
    return Sample(name, kin, feed, length, [&](double u, Eigen::Vector3d& tip, Eigen::Vector3d& axis) {
      const double phi = 2 * kPi * turns * u;
      const Eigen::Vector3d radial(std::cos(phi), std::sin(phi), 0);
      tip = Eigen::Vector3d(0, 0, 20 - drop * u) + radius * radial;
      axis = (std::cos(lean) * Eigen::Vector3d::UnitZ() + std::sin(lean) * radial).normalized();
    });
  }
  if (name == "inclined-pocket") {
    // A 60 × 40 mm pocket outline in a plane inclined 25° about X and 15°
    // about Y, tool normal to the plane: four sharp corners (exact stops),
    // the linear axes moving together on every side.
    const Eigen::Matrix3d incline = (Eigen::AngleAxisd(15 * kDeg, Eigen::Vector3d::UnitY()) *
                                     Eigen::AngleAxisd(25 * kDeg, Eigen::Vector3d::UnitX()))
                                        .toRotationMatrix();
    const Eigen::Vector3d axis = incline * Eigen::Vector3d::UnitZ();
    const Kinematics::RotaryAngles angles = kin.AnglesFor(axis, {});
    ToolPath path;
    path.name = name;
    const double corners[5][2] = {{-30, -20}, {30, -20}, {30, 20}, {-30, 20}, {-30, -20}};
    for (const auto& c : corners)
      AddFeedVertex(path, Eigen::Vector3d(0, 0, 10) + incline * Eigen::Vector3d(c[0], c[1], 0), angles, feed);
    return path;
  }
  throw InputError("command line", 0, "--path",
                   fmt::format("'{}' is not a test path (cone, s-shape, inclined-circle, helix, inclined-pocket)", name));
}

void CheckAxisRanges(const ToolPath& path, const FiveAxisMachine& m, const std::string& source) {
  const auto names = m.axis_names();
  const Kinematics kin(m.kinematics);
  for (std::size_t i = 0; i < path.vertices.size(); ++i) {
    const PathVertex& v = path.vertices[i];
    const int line = v.source_line;
    const std::string where = line > 0 ? "" : fmt::format(" (vertex {})", i);
    if (v.tilt_deg < m.tilt_min_deg || v.tilt_deg > m.tilt_max_deg)
      throw InputError(source, line, names[kTilt],
                       fmt::format("{} = {:.4f} deg is outside the machine's range {} … {} deg{}", names[kTilt],
                                   v.tilt_deg, m.tilt_min_deg, m.tilt_max_deg, where));
    if (v.rot_deg < m.rot_min_deg || v.rot_deg > m.rot_max_deg)
      throw InputError(source, line, names[kRot],
                       fmt::format("{} = {:.4f} deg is outside the machine's range {} … {} deg{}", names[kRot],
                                   v.rot_deg, m.rot_min_deg, m.rot_max_deg, where));
    const AxisVector joints = kin.Inverse(v.tip_mm, v.tilt_deg, v.rot_deg);
    for (int k = 0; k < 3; ++k)
      if (!(joints[k] >= m.travel_min_mm[k] && joints[k] <= m.travel_max_mm[k]))
        throw InputError(source, line, names[k],
                         fmt::format("the tip ({:g}, {:g}, {:g}) mm needs {} = {:.4f} mm, outside the machine's travel "
                                     "{:g} … {:g} mm{}",
                                     v.tip_mm.x(), v.tip_mm.y(), v.tip_mm.z(), names[k], joints[k],
                                     m.travel_min_mm[k], m.travel_max_mm[k], where));
  }
}

}  // namespace trueaxis::fiveaxis
