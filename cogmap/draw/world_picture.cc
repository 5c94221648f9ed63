#include "cogmap/draw/world_picture.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace cogmap::draw {
namespace {

const Colour kRoomFills[] = {Rgb8(235, 242, 255), Rgb8(255, 245, 230), Rgb8(235, 255, 240), Rgb8(250, 235, 250),
                             Rgb8(255, 255, 225)};
const Colour kCorridorFill = Rgb8(238, 238, 238);
const Colour kDoorColour = Rgb8(255, 150, 0);
const Colour kRoomText = Rgb8(60, 60, 110);

struct Bounds {
  Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  Vec2 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  void Grow(const Vec2& p) {
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool empty() const { return lo.x() > hi.x(); }
};

MapPicture Finish(Drawing d, MapPage& page, const LabelPlacer& placer) {
  MapPicture out;
  out.drawing = std::move(d);
  out.px_per_m = page.px_per_m();
  out.scale_bar = page.scale_bar();
  out.map_box = page.map_box();
  out.origin_px = page.Px(Vec2(0, 0));
  out.labels_placed = placer.placed();
  out.labels_dropped = placer.dropped();
  return out;
}

void HomeArrow(Drawing& d, const MapPage& page, const Pose2& home, Colour c) {
  const double k = page.px_per_m();
  const Vec2 p = page.Px(home.translation());
  const double r = std::clamp(0.13 * k, 3.0, 8.0);
  d.Circle(p, r, c);
  const Vec2 t = p + Vec2(std::cos(home.theta), -std::sin(home.theta)) * std::max(3 * r, 10.0);
  d.Line(p, t, Stroke{c, std::max(1.5, r / 2)});
}

}  // namespace

MapPicture DrawWorld(const FloorPlan& world, const std::vector<Vec2>& truth, const std::vector<Vec2>& odom,
                     const PictureOptions& options) {
  Bounds b;
  b.Grow(world.min);
  b.Grow(world.max);
  for (const auto& w : world.walls) b.Grow(w.a), b.Grow(w.b);
  for (const auto& v : truth) b.Grow(v);
  for (const auto& v : odom) b.Grow(v);
  if (b.empty()) b.Grow(Vec2(0, 0));
  std::vector<LegendItem> legend = {{LegendItem::Kind::kLine, kBlack, "walls"},
                                    {LegendItem::Kind::kLine, kDoorColour, "doorways"}};
  if (!world.route.empty()) legend.push_back({LegendItem::Kind::kDisc, Rgb8(60, 90, 255), "route"});
  if (!truth.empty()) legend.push_back({LegendItem::Kind::kLine, Rgb8(0, 170, 0), "true path"});
  if (!odom.empty()) legend.push_back({LegendItem::Kind::kLine, Rgb8(230, 0, 0), "odometry"});
  MapPage page(b.lo, b.hi, options, legend);
  Drawing d = page.NewDrawing();
  const double k = page.px_per_m();
  for (size_t i = 0; i < world.rooms.size(); ++i) {
    const auto& r = world.rooms[i];
    const Vec2 a = page.Px(Vec2(r.min.x(), r.max.y())), c = page.Px(Vec2(r.max.x(), r.min.y()));
    d.Rectangle(Box{a.x(), a.y(), c.x(), c.y()}, kRoomFills[i % 5]);
  }
  const double wall_px = std::clamp(0.05 * k, 1.5, 5.0);
  for (const auto& w : world.walls) d.Line(page.Px(w.a), page.Px(w.b), Stroke{kBlack, wall_px});
  for (const auto& dw : world.doorways) d.Line(page.Px(dw.line.a), page.Px(dw.line.b), Stroke{kDoorColour, wall_px});
  for (const auto& wp : world.route) d.Circle(page.Px(wp.pose.translation()), std::clamp(0.06 * k, 2.0, 5.0), Rgb8(60, 90, 255));
  d.Polyline(page.Px(odom), Stroke{Rgb8(230, 0, 0), std::clamp(0.03 * k, 1.0, 2.5)});
  d.Polyline(page.Px(truth), Stroke{Rgb8(0, 170, 0), std::clamp(0.03 * k, 1.0, 2.5)});
  if (world.home) HomeArrow(d, page, *world.home, Rgb8(0, 120, 0));
  LabelPlacer placer(page.map_box());  // labels stay over the map, off the bands
  for (const auto& box : page.Decorate(d)) placer.Block(box);
  const Font font{std::clamp(0.35 * k, 10.0, 15.0)};
  for (const auto& r : world.rooms)
    if (!r.name.empty()) placer.Label(d, page.Px(0.5 * (r.min + r.max)), r.name, font, kRoomText);
  return Finish(std::move(d), page, placer);
}

MapPicture DrawPlan(const plan::Plan& plan, const PlanPictureOptions& options) {
  Bounds b;
  b.Grow(plan.min);
  b.Grow(plan.max);
  for (const auto& w : plan.walls)
    for (const auto& p : w.points) b.Grow(p);
  for (const auto& r : plan.rooms)
    for (const auto& p : r.polygon) b.Grow(p);
  if (b.empty()) b.Grow(Vec2(0, 0));
  std::vector<LegendItem> legend = {{LegendItem::Kind::kLine, kBlack, "walls"},
                                    {LegendItem::Kind::kFill, kRoomFills[0], "rooms"},
                                    {LegendItem::Kind::kFill, kCorridorFill, "corridors"},
                                    {LegendItem::Kind::kLine, kDoorColour, "doors"}};
  if (options.room_graph) legend.push_back({LegendItem::Kind::kDashed, Rgb8(120, 70, 170), "room graph"});
  MapPage page(b.lo, b.hi, options.picture, legend);
  Drawing d = page.NewDrawing();
  const double k = page.px_per_m();
  std::map<int, const plan::Room*> rooms;
  for (const auto& r : plan.rooms) rooms[r.id] = &r;
  int tint = 0;
  for (const auto& r : plan.rooms)
    d.Polygon(page.Px(r.polygon), r.corridor ? kCorridorFill : kRoomFills[tint++ % 5],
              Stroke{Rgb8(180, 180, 190), 0.8, {}, false});
  const double wall_px = std::clamp(0.1 * k, 2.0, 6.0);
  for (const auto& w : plan.walls) d.Polyline(page.Px(w.points), Stroke{kBlack, wall_px, {}, false});
  // Doors: the opening in orange with a short tick at each jamb across it.
  for (const auto& door : plan.doors) {
    const Vec2 a = page.Px(door.a), c = page.Px(door.b);
    d.Line(a, c, Stroke{kDoorColour, std::max(1.5, wall_px * 0.6), {}, false});
    const Vec2 dir = c - a;
    if (dir.norm() > 1e-9) {
      const Vec2 n = Vec2(-dir.y(), dir.x()).normalized() * std::max(4.0, wall_px * 1.5);
      d.Line(a - n, a + n, Stroke{kDoorColour, 1.5, {}, false});
      d.Line(c - n, c + n, Stroke{kDoorColour, 1.5, {}, false});
    }
  }
  if (options.room_graph) {
    const Stroke s{Rgb8(120, 70, 170), 1.5, {5, 4}, false};
    for (const auto& e : plan.edges) {
      const auto ra = rooms.find(e.room_a), rb = rooms.find(e.room_b);
      if (ra == rooms.end() || rb == rooms.end()) continue;
      const plan::Door* door = nullptr;
      for (const auto& x : plan.doors)
        if (x.id == e.door) door = &x;
      std::vector<Vec2> pts = {page.Px(ra->second->label)};
      if (door) pts.push_back(page.Px(door->center()));
      pts.push_back(page.Px(rb->second->label));
      d.Polyline(pts, s);
    }
  }
  if (plan.home) HomeArrow(d, page, *plan.home, Rgb8(0, 120, 0));
  LabelPlacer placer(page.map_box());  // labels stay over the map, off the bands
  for (const auto& box : page.Decorate(d)) placer.Block(box);
  if (options.labels) {
    const Font font{std::clamp(0.3 * k, 10.0, 14.0)};
    for (const auto& r : plan.rooms) {
      char area[32];
      std::snprintf(area, sizeof area, "%.1f m²", r.area_m2);
      const std::string text = r.name.empty() ? std::string(area) : r.name + " · " + area;
      placer.Label(d, page.Px(r.label), text, font, kRoomText);
    }
  }
  return Finish(std::move(d), page, placer);
}

}  // namespace cogmap::draw
