#pragma once
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap {

// A named axis-aligned rectangle (ground-truth room extent), metres.
struct NamedBox {
  std::string name;
  Vec2 min;
  Vec2 max;
  bool Contains(const Vec2& p) const {
    return p.x() >= min.x() && p.x() <= max.x() && p.y() >= min.y() && p.y() <= max.y();
  }
};

// A named line (ground-truth door opening), metres.
struct NamedSegment {
  std::string name;
  Segment2 line;
};

struct Waypoint {
  std::string name;
  Pose2 pose;  // heading CCW, radians
};

// A building as the simulator and the evaluation see it: walls, the truth
// about rooms and doors, the robot's start and its route. World frame, metres.
struct FloorPlan {
  std::vector<Segment2> walls;
  std::vector<NamedBox> rooms;
  std::vector<NamedSegment> doorways;
  std::optional<Pose2> home;
  std::vector<Waypoint> route;  // in order of their wpNN names
  Vec2 min{0, 0};               // LineMinPos
  Vec2 max{0, 0};               // LineMaxPos
};

// Ground-truth rooms as a raster, from a room-segmentation image (a
// building's map with every room's floor filled; io::ReadRoomSegmentation).
// Cell (x, y) covers [origin.x + x cell_m, + cell_m) x [origin.y + y cell_m,
// + cell_m), y up (row 0 is the bottom row); its label is -1 (no room: a
// wall, the outside, unlabelled floor) or the index of its room.
struct RoomLabels {
  Vec2 origin{0, 0};
  double cell_m = 0.05;
  int width = 0, height = 0;
  std::vector<int32_t> label;      // width x height, row-major
  std::vector<std::string> names;  // per room
  std::vector<int64_t> cells;      // per room: its number of cells
  bool empty() const { return names.empty(); }
  int At(const Vec2& p) const {
    const double fx = std::floor((p.x() - origin.x()) / cell_m), fy = std::floor((p.y() - origin.y()) / cell_m);
    if (!(fx >= 0 && fy >= 0 && fx < width && fy < height)) return -1;
    return label[static_cast<size_t>(fy) * width + static_cast<size_t>(fx)];
  }
};

}  // namespace cogmap
