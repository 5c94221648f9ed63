#pragma once
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

}  // namespace cogmap
