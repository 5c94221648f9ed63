#pragma once
// Pictures of worlds (the truth) and of the floor plan cogmap builds.
#include <vector>

#include "cogmap/core/floor_plan.h"
#include "cogmap/core/geometry.h"
#include "cogmap/draw/map_picture.h"
#include "cogmap/plan/plan.h"

namespace cogmap::draw {

// A world: rooms filled lightly with their names, walls, doorways, the route's
// waypoints, the home pose, and (when given) the true path (green) and the
// odometry path (red).
MapPicture DrawWorld(const FloorPlan& world, const std::vector<Vec2>& true_path, const std::vector<Vec2>& odometry_path,
                     const PictureOptions& options = {});

struct PlanPictureOptions {
  PictureOptions picture{.title = "Floor plan"};
  bool room_graph = false;  // edges room label -> door -> room label
  bool labels = true;       // room name and area
};

// The floor plan: room polygons filled lightly (corridors in another tint),
// each labelled with its name and area (placed without overlap), walls,
// doors as a gap mark across the opening, the home pose, and optionally the
// room graph.
MapPicture DrawPlan(const plan::Plan& plan, const PlanPictureOptions& options = {});

}  // namespace cogmap::draw
