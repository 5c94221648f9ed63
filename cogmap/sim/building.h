#pragma once
#include <cstdint>

#include "cogmap/core/floor_plan.h"

namespace cogmap::sim {

// A synthetic office floor for scale tests: one straight corridor along x with
// rooms on both sides, each joined to the corridor by one door.
struct BuildingOptions {
  int rooms = 100;
  double corridor_m = 1000.0;     // corridor length
  double corridor_width_m = 2.0;
  double room_depth_m = 6.0;      // rooms reach this far from the corridor
  double door_width_m = 0.9;
  double width_jitter = 0.2;      // room widths vary by up to +-20 % of the mean
  uint64_t seed = 1;
  // Not 0: a second wing, generated alike (seed + 1), turned by this many
  // degrees (CCW, at most 60 either way) and joined to the east end of the
  // first by a straight stretch of corridor, as buildings whose wings meet
  // at an angle are. Its rooms have no truth boxes (a 2D-Map's room extents
  // are axis-aligned); its walls, doors and route are turned with it.
  double wing_deg = 0.0;
  // Not 0: every wall this thick, drawn as its two faces and its two ends
  // around the line it would be (the thesis's worlds and a 2D-Map's walls
  // are lines: one face each side, no thickness). Doors keep their width
  // (a corridor wall's piece ends square at the jamb); where walls meet,
  // the ends and faces that fall inside another wall are hidden from the
  // sensors by its faces. Rooms keep their truth boxes, to the walls' middle
  // lines.
  double wall_m = 0.0;
};

// Walls, Room and Doorway truth (the corridor is a room named "corridor"),
// RobotHome at the west end of the corridor, and a route that visits every
// room (corridor in front of the door, room centre, back to the corridor),
// with waypoints named wp0001, wp0002, ... Throws InputError when the rooms
// cannot fit (each room needs at least 2 m of corridor), or a size is no
// number or more than a building has (a corridor of 100 km, 50 m wide, rooms
// 100 m deep, doors 10 m wide, 100000 rooms, walls 1 m thick; the walls at
// most a quarter of the corridor's width).
FloorPlan GenerateBuilding(const BuildingOptions& options);

}  // namespace cogmap::sim
