#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "cogmap/grid/map_limits.h"
#include "cogmap/sim/world.h"

namespace cogmap::sim {

// The robot's configuration space on a grid: a cell is passable when its centre
// is at least robot radius + margin from every wall (then no straight move
// between two adjacent passable centres can touch a wall). Also marks the
// cells that walls cross (the obstacle cells the VFH histogram is built from).
class NavGrid {
 public:
  NavGrid(const World& world, const grid::MapLimits& limits, double robot_radius_m, double margin_m);

  const grid::MapLimits& limits() const { return limits_; }
  bool Passable(long flat) const { return passable_[flat] != 0; }
  bool WallCell(long flat) const { return wall_[flat] != 0; }
  bool Passable(const Vec2& p) const;

  // The passable cell nearest to 'p' within 'within_m' (-1 if none).
  long NearestPassable(const Vec2& p, double within_m) const;

  // Breadth-first search (8-connected) over passable cells from 'start' until a
  // cell for which 'is_goal' holds is reached. Returns the cells from 'start'
  // to that cell, both included; empty when no goal cell is reachable.
  std::vector<long> FindPath(long start, const std::function<bool(long)>& is_goal) const;

  // True when every sample along [a, b] (every half cell) lies in a passable cell.
  bool PassableLine(const Vec2& a, const Vec2& b) const;

 private:
  grid::MapLimits limits_;
  std::vector<uint8_t> passable_, wall_;
  mutable std::vector<int32_t> parent_;  // BFS scratch
  mutable std::vector<uint32_t> stamp_;
  mutable uint32_t generation_ = 0;
};

// A grid covering the walls' bounding box (and 'extra' points) plus a margin.
grid::MapLimits LimitsAround(const World& world, const std::vector<Vec2>& extra, double cell_m,
                             double margin_m);

}  // namespace cogmap::sim
