#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/pose2.h"
#include "cogmap/sim/nav_grid.h"

namespace cogmap::sim {

// Vector Field Histogram (Borenstein & Koren 1991; SPEC 6): the certainty
// cells in a window around the robot vote into a polar histogram of 5 degree
// sectors with magnitude c^2 (a - b d); sectors above the threshold are
// blocked; the robot steers to the free valley nearest the goal direction.
// Obstacle cells are enlarged by the robot radius plus a safety distance
// (as in VFH+), so that a free sector is one the robot's body fits through.
struct VfhOptions {
  double sector_rad = 0.087266462599716;  // 5 degrees (SPEC 6)
  double window_radius_m = 2.0;           // active window
  double a = 1.0;                         // a - b * d_max = 0 at the window edge
  double b = 0.5;
  double threshold = 1.0;                 // histogram value above which a sector is blocked
  double safety_m = 0.05;                 // added to the robot radius for enlargement
  int wide_valley_sectors = 16;           // s_max: a valley at least this wide is "wide"
};

struct VfhResult {
  bool free = false;           // some sector is free
  double heading_rad = 0.0;    // chosen direction (world frame)
  std::vector<double> histogram;  // per sector, sector k centred on -pi + (k + 0.5) * sector
};

// Builds the histogram from the wall cells of 'nav' around 'position' (the
// certainty c is 1 on every wall cell: the simulator knows its walls, see
// docs/simulator.md) and chooses a heading toward 'goal_heading_rad'. Cells
// farther than 'goal_distance_m' + radius + safety are left out: a wall
// behind the goal must not keep the robot from reaching it.
VfhResult VfhSteer(const NavGrid& nav, const Vec2& position, double goal_heading_rad,
                   double robot_radius_m, const VfhOptions& options = {},
                   double goal_distance_m = 1e9);

// The same from a certainty grid over 'limits' (e.g. built from the robot's
// own readings, HIMM-style): cell certainty c = value / c_max in [0, 1].
VfhResult VfhSteerCertainty(const grid::MapLimits& limits, const std::vector<uint8_t>& certainty,
                            double c_max, const Vec2& position, double goal_heading_rad,
                            double robot_radius_m, const VfhOptions& options = {},
                            double goal_distance_m = 1e9);

// The valley selection alone, on a given histogram (for tests).
VfhResult VfhChoose(std::vector<double> histogram, double goal_heading_rad, const VfhOptions& options);

}  // namespace cogmap::sim
