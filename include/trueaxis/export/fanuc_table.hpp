#pragma once
// FANUC pitch error compensation as a parameter-tape-like text (docs/export.md).
//
// Parameters of the axis (axis-type parameters "N0xxxxA<axis>P<value>"):
//   3620 number of the compensation point of the reference position
//   3621 number of the farthest point on the − side
//   3622 number of the farthest point on the + side
//   3623 magnification (value × magnification × detection unit is output)
//   3624 interval between points (written in detection units)
//   bidirectional (3605#0 = 1): 3626 farthest − point of the reverse-travel
//   table, 3627 absolute compensation at the reference position when it is
//   approached in the other direction (detection units)
//   unidirectional: 1851 backlash (detection units)
// Pitch data: "N1nnnnP<value>" for compensation point nnnn.
//
// Point m lies at ref + (m − 3620)·interval; its value is the INCREMENT of the
// correction over the interval ENDING at it ([x_m − interval, x_m]); the
// farthest − point is 3620 − (points below the reference) + 1. The correction
// at the reference position is 0 by construction (reference return sets the
// machine position), so the table is zeroed there. Values are integers: the
// cumulative correction is rounded and differenced ("carried rounding"), so
// rounding never accumulates along the axis.
#include <limits>
#include <string>
#include <string_view>

#include "trueaxis/export/compensation_table.hpp"

namespace trueaxis::exporter {

struct FanucOptions {
  int axis_number = 1;              // A<n>: 1 = first controlled axis
  double detection_unit_um = 1.0;   // 1 µm for IS-B metric
  int magnification = 0;            // 3623; 0: the smallest 1…100 whose increments fit point_limit
  int point_limit = 7;              // |value| per point, in magnification × detection units
  int reference_point_number = -1;  // 3620; −1: derived so the axis starts its own block of the
                                    // shared pool: A<n> from (n−1)·(max_point_number+1)/axes_sharing_pool
  int axes_sharing_pool = 4;        // axes the pool of point numbers is divided between by default
  int reverse_first_number = -1;    // 3626; −1: right after the forward block
  int max_point_number = 1023;
  double max_feed_mm_per_min = std::numeric_limits<double>::quiet_NaN();  // if given: interval ≥ feed/7500
  bool IsValid(std::string* why) const;
};

struct FanucResult {
  std::string tape;
  int magnification = 0;
  int reference_point_number = 0, min_point_number = 0, max_point_number = 0;
  int reverse_min_point_number = -1;
  double max_rounding_um = 0;  // |applied − table| at the points, µm
  std::string Instructions() const;
};

// The table must be equidistant, hold its reference position as a point, and
// be zero there in the forward column (resample with zero_at_reference).
FanucResult WriteFanucPitchTape(const CompensationTable& table, const FanucOptions& options, const std::string& source);

// Reads a tape back; the reference position's machine coordinate is not in
// the tape (it is where reference return puts the axis), so it is given.
CompensationTable ReadFanucPitchTape(std::string_view text, int axis_number, double detection_unit_um,
                                     double reference_position_mm, const std::string& source);

}  // namespace trueaxis::exporter
