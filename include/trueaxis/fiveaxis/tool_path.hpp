#pragma once
// A programmed tool path: vertices in the workpiece frame (tool tip mm,
// rotary angles deg), each with the move that reaches it (docs/fiveaxis.md).
// Between vertices the CNC moves the tip on a straight line and the rotary
// axes linearly (TCP mode, as LinuxCNC's trt kinematics).
#include <string>
#include <vector>

#include "trueaxis/fiveaxis/machine.hpp"

namespace trueaxis::fiveaxis {

enum class MoveKind { kStart, kRapid, kFeed, kInverseTime };

struct PathVertex {
  Eigen::Vector3d tip_mm = Eigen::Vector3d::Zero();
  double tilt_deg = 0, rot_deg = 0;
  MoveKind move = MoveKind::kFeed;
  double feed_mm_per_min = 0;    // kFeed
  double duration_s = 0;         // kInverseTime (G93: F = 1 / minutes)
  int source_line = 0;           // program line, 0 when generated
};

struct ToolPath {
  std::string name;
  // Where the feeds come from, for errors: the word or column of a program
  // ("F", "feed_mm_per_min", "duration_s") or the option of a generated path ("--feed").
  std::string feed_field = "feed";
  std::vector<PathVertex> vertices;  // vertices[0] is the start (MoveKind::kStart)
};

// Built-in test paths (docs/fiveaxis.md "Test paths"), at the given feed; the
// rotary angles come from the machine's kinematics (nearest solution, C
// continuous). Names: "cone" (NAS 979 / ISO 10791-7 cone frustum), "s-shape",
// "inclined-circle".
std::vector<std::string> TestPathNames();
ToolPath MakeTestPath(const std::string& name, const Kinematics& kin, double feed_mm_per_min);

// Refuses rotary values outside the machine's ranges, and vertices whose
// linear joints (inverse kinematics) lie outside its X/Y/Z travel: InputError
// naming the source line (or the vertex index for generated paths).
void CheckAxisRanges(const ToolPath& path, const FiveAxisMachine& m, const std::string& source);

}  // namespace trueaxis::fiveaxis
