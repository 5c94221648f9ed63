#include "cogmap/sim/building.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "cogmap/core/error.h"

namespace cogmap::sim {

namespace {
FloorPlan OneWing(const BuildingOptions& o);

// The plan's box: the least and the most of its walls' ends.
void FitBoundsToWalls(FloorPlan* plan) {
  plan->min = plan->max = plan->walls.front().a;
  for (const Segment2& w : plan->walls)
    for (const Vec2& p : {w.a, w.b}) {
      plan->min = plan->min.cwiseMin(p);
      plan->max = plan->max.cwiseMax(p);
    }
}

// Two wings: 'a' along x from 0 to its corridor's length, 'b' turned by
// wing_deg about the far end of a joining corridor.
FloorPlan TwoWings(const BuildingOptions& o) {
  BuildingOptions one = o;
  one.wing_deg = 0.0;
  FloorPlan plan = OneWing(one);
  one.seed = o.seed + 1;
  const FloorPlan b = OneWing(one);
  const double L = o.corridor_m, W = o.corridor_width_m, D = o.room_depth_m;
  const double th = DegToRad(o.wing_deg), c = std::cos(th), s = std::sin(th);
  // The joint is long enough that the turned wing's rooms on the inside of
  // the turn clear the first wing's.
  const double J = (0.5 * W + D) * std::abs(s) + 1.0;
  const Vec2 pivot(L + J, 0.5 * W);
  auto turned = [&](const Vec2& p) {
    const Vec2 q(p.x(), p.y() - 0.5 * W);
    return Vec2(pivot.x() + c * q.x() - s * q.y(), pivot.y() + s * q.x() + c * q.y());
  };
  auto near = [](double a, double b) { return std::abs(a - b) < 1e-9; };
  // The first wing's east end and the second's west end stay only where
  // they close rooms.
  std::vector<Segment2> walls;
  for (const Segment2& w : plan.walls) {
    if (near(w.a.x(), L) && near(w.b.x(), L) && std::min(w.a.y(), w.b.y()) < 0.0 && std::max(w.a.y(), w.b.y()) > W) {
      walls.push_back({{L, -D}, {L, 0.0}});
      walls.push_back({{L, W}, {L, W + D}});
    } else {
      walls.push_back(w);
    }
  }
  // The joint: the inside of the turn straight on to where the turned
  // corridor's wall meets it, the outside to the pivot and round.
  const double inner = o.wing_deg > 0 ? W : 0.0, outer = o.wing_deg > 0 ? 0.0 : W;
  const double t = 0.5 * W * std::tan(0.5 * std::abs(th));
  walls.push_back({{L, inner}, {turned(Vec2(t, inner)).x(), inner}});
  walls.push_back({{L, outer}, {pivot.x(), outer}});
  walls.push_back({{pivot.x(), outer}, turned(Vec2(0.0, outer))});
  for (Segment2 w : b.walls) {
    if (near(w.a.x(), 0.0) && near(w.b.x(), 0.0) && std::min(w.a.y(), w.b.y()) < 0.0 &&
        std::max(w.a.y(), w.b.y()) > W) {
      // The room on the inside of the turn: its west wall reaches the
      // joint's wall before the corridor's, and stops there.
      for (const auto& [far, edge] : {std::pair{Vec2(0.0, -D), Vec2(0.0, 0.0)}, std::pair{Vec2(0.0, W + D), Vec2(0.0, W)}}) {
        const Vec2 p = turned(far);
        Vec2 q = turned(edge);
        if ((p.y() - inner) * (q.y() - inner) < 0.0) q = p + (q - p) * ((inner - p.y()) / (q.y() - p.y()));
        walls.push_back({p, q});
      }
      continue;
    }
    if (near(w.a.y(), inner) && near(w.b.y(), inner)) {
      if (near(w.a.x(), 0.0)) w.a.x() = t;
      if (near(w.b.x(), 0.0)) w.b.x() = t;
    }
    walls.push_back({turned(w.a), turned(w.b)});
  }
  plan.walls = std::move(walls);
  for (const NamedSegment& d : b.doorways)
    plan.doorways.push_back({d.name + "b", {turned(d.line.a), turned(d.line.b)}});
  // The route on through the joint and round the turned wing.
  std::vector<Pose2> route;
  for (const Waypoint& w : plan.route) route.push_back(w.pose);
  route.push_back(Pose2{L + 0.5 * J, 0.5 * W, 0.0});
  route.push_back(Pose2{pivot.x(), pivot.y(), th});
  for (const Waypoint& w : b.route) {
    const Vec2 p = turned(w.pose.translation());
    route.push_back(Pose2{p.x(), p.y(), NormalizeAngle(w.pose.theta + th)});
  }
  plan.route.clear();
  for (size_t k = 0; k < route.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "wp%04zu", k + 1);
    plan.route.push_back({name, route[k]});
  }
  FitBoundsToWalls(&plan);
  return plan;
}
}  // namespace

FloorPlan GenerateBuilding(const BuildingOptions& o) {
  if (!std::isfinite(o.wing_deg) || std::abs(o.wing_deg) > 60.0)
    throw InputError("gen-building: a wing turned by at most 60 degrees either way");
  // Sizes a building can have (and numbers at all: NaN and infinities are
  // none), before anything is allocated: a 2D-Map holds whole millimetres.
  auto within = [](const char* option, double v, double hi) {
    if (std::isfinite(v) && v <= hi) return;
    char text[128];
    std::snprintf(text, sizeof text, "gen-building: %s %g: at most %g m", option, v, hi);
    throw InputError(text);
  };
  within("--corridor-m", o.corridor_m, 100000.0);
  within("--corridor-width-m", o.corridor_width_m, 50.0);
  within("--room-depth-m", o.room_depth_m, 100.0);
  within("--door-m", o.door_width_m, 10.0);
  if (o.rooms > 100000) throw InputError("gen-building: --rooms " + std::to_string(o.rooms) + ": at most 100000");
  if (!(o.wall_m >= 0.0)) throw InputError("gen-building: --wall-m must be 0 or more");
  within("--wall-m", o.wall_m, std::min(1.0, 0.25 * o.corridor_width_m));
  FloorPlan plan = o.wing_deg != 0.0 ? TwoWings(o) : OneWing(o);
  if (o.wall_m > 0.0) {
    // Each wall's line becomes the outline of a wall wall_m thick: two
    // faces and two ends (a wall of zero length stays none).
    const double h = 0.5 * o.wall_m;
    std::vector<Segment2> thick;
    for (const Segment2& w : plan.walls) {
      const Vec2 d = w.b - w.a;
      const double len = d.norm();
      if (!(len > 1e-9)) continue;
      const Vec2 n = Vec2(-d.y(), d.x()) * (h / len);
      const Vec2 a0 = w.a + n, a1 = w.a - n, b0 = w.b + n, b1 = w.b - n;
      thick.push_back({a0, b0});
      thick.push_back({a1, b1});
      thick.push_back({a0, a1});
      thick.push_back({b0, b1});
    }
    plan.walls = std::move(thick);
    FitBoundsToWalls(&plan);
  }
  return plan;
}

namespace {
FloorPlan OneWing(const BuildingOptions& o) {
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
}  // namespace

}  // namespace cogmap::sim
