#pragma once
// The floor plan (issue 11): one wall per physical wall face, rooms as
// non-overlapping polygons, doors as gaps, and the room graph through them.
// Made from the placed ASRs (the pose graph's poses) and the store's room ids.
// Everything is in the map frame: metres, x east, y north (the raw odometry
// frame of the first run, as placed by the correction).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/geometry.h"
#include "cogmap/core/pose2.h"

namespace cogmap::plan {

// One wall face: the evidence of every ASR that saw this face, fused.
struct Wall {
  Polyline points;            // >= 2 distinct points, map frame
  bool free_on_left = true;   // free space lies left of the direction first -> last point
  double weight = 0.0;        // evidence behind it (metres of wall seen, weighted by quality)
  std::vector<int> asr_ids;   // the ASRs whose walls were fused into it
  bool squared = false;       // snapped to one of the building's dominant directions
};

// An exit the robot passed, as a gap in the walls.
struct Door {
  int id = -1;
  Vec2 a{0, 0}, b{0, 0};      // the gap's ends (the jambs), map frame
  int room_a = -1;            // plan room on each side (-1: none)
  int room_b = -1;
  int from_asr = -1;          // the exit's ASRs (asr::Exit)
  int to_asr = -1;
  Vec2 center() const { return 0.5 * (a + b); }
  double width_m() const { return (b - a).norm(); }
};

// A room (or a whole corridor) of the plan.
struct Room {
  int id = -1;
  std::string name;              // "Room 3", "Corridor 1"
  bool corridor = false;
  std::vector<Vec2> polygon;     // counter-clockwise, simple, first point not repeated
  double area_m2 = 0.0;
  Vec2 label{0, 0};              // a point inside the polygon for its label
  std::vector<int> doors;        // Door ids
  std::vector<int> asr_ids;      // ASRs drawn as this room
  std::vector<int> graph_rooms;  // store room ids (asr::SqliteAsrStore::RoomOf) it shows
};

// The room graph: plan rooms joined through a door.
struct Edge {
  int room_a = -1;
  int room_b = -1;
  int door = -1;
};

struct Plan {
  std::vector<Wall> walls;
  std::vector<Room> rooms;
  std::vector<Door> doors;
  std::vector<Edge> edges;
  std::optional<Pose2> home;  // the robot's first pose
  Vec2 min{0, 0}, max{0, 0};  // bounds of walls and rooms
};

}  // namespace cogmap::plan
