#include "cogmap/sim/building.h"

#include <algorithm>
#include <cstdio>
#include <random>

#include "cogmap/core/error.h"

namespace cogmap::sim {

FloorPlan GenerateBuilding(const BuildingOptions& o) {
  if (o.rooms < 1) throw InputError("gen-building: need at least 1 room");
  if (!(o.corridor_width_m >= 1.0) || !(o.room_depth_m >= 2.0) || !(o.door_width_m >= 0.7))
    throw InputError("gen-building: corridor width >= 1 m, room depth >= 2 m and door width >= 0.7 m needed");
  const int south = (o.rooms + 1) / 2, north = o.rooms / 2;
  if (!(o.corridor_m / south >= 2.0) || !(o.corridor_m / south >= o.door_width_m + 1.0))
    throw InputError("gen-building: a corridor of " + std::to_string(o.corridor_m) + " m is too short for " +
                     std::to_string(o.rooms) + " rooms (each needs 2 m)");
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  const double L = o.corridor_m, W = o.corridor_width_m, D = o.room_depth_m;

  FloorPlan plan;
  auto wall = [&](double x1, double y1, double x2, double y2) {
    if (std::abs(x1 - x2) + std::abs(y1 - y2) > 1e-9) plan.walls.push_back({{x1, y1}, {x2, y2}});
  };
  // Outline.
  wall(0, -D, L, -D);
  wall(L, -D, L, W + D);
  wall(L, W + D, 0, W + D);
  wall(0, W + D, 0, -D);
  plan.rooms.push_back({"corridor", {0, 0}, {L, W}});

  struct Door { double x; bool north; std::string room; Vec2 centre; };
  std::vector<Door> doors;
  int room_no = 0;
  for (int side = 0; side < 2; ++side) {
    const int n = side == 0 ? south : north;
    if (n == 0) {
      wall(0, side == 0 ? 0 : W, L, side == 0 ? 0 : W);
      continue;
    }
    // Split points with jittered widths.
    std::vector<double> x{0.0};
    const double mean = L / n;
    for (int i = 1; i < n; ++i) x.push_back(i * mean + u(rng) * o.width_jitter * mean * 0.5);
    x.push_back(L);
    const double y_wall = side == 0 ? 0.0 : W;
    const double y_far = side == 0 ? -D : W + D;
    double cursor = 0.0;
    for (int i = 0; i < n; ++i) {
      const double x0 = x[i], x1 = x[i + 1];
      if (i > 0) wall(x0, y_wall, x0, y_far);
      const double margin = 0.3;
      const double span = (x1 - x0) - 2 * margin - o.door_width_m;
      const double d0 = x0 + margin + std::max(0.0, span) * u01(rng);
      wall(cursor, y_wall, d0, y_wall);
      cursor = d0 + o.door_width_m;
      char name[32];
      std::snprintf(name, sizeof name, "room%d", ++room_no);
      plan.rooms.push_back({name, {x0, std::min(y_wall, y_far)}, {x1, std::max(y_wall, y_far)}});
      char dname[32];
      std::snprintf(dname, sizeof dname, "door%d", room_no);
      plan.doorways.push_back({dname, {{d0, y_wall}, {d0 + o.door_width_m, y_wall}}});
      doors.push_back({d0 + 0.5 * o.door_width_m, side == 1, name,
                       {0.5 * (x0 + x1), 0.5 * (y_wall + y_far)}});
    }
    wall(cursor, y_wall, L, y_wall);
  }
  std::sort(doors.begin(), doors.end(), [](const Door& a, const Door& b) { return a.x < b.x; });
  plan.home = Pose2{std::min(1.0, 0.25 * L), 0.5 * W, 0.0};
  int k = 0;
  auto add = [&](const Vec2& p, double th) {
    char name[32];
    std::snprintf(name, sizeof name, "wp%04d", ++k);
    plan.route.push_back({name, {p.x(), p.y(), th}});
  };
  for (const auto& d : doors) {
    const double in = d.north ? kPi / 2 : -kPi / 2;
    add({d.x, 0.5 * W}, in);
    add(d.centre, in);
    add({d.x, 0.5 * W}, 0.0);
  }
  plan.min = Vec2(0, -D);
  plan.max = Vec2(L, W + D);
  return plan;
}

}  // namespace cogmap::sim
