#include "cogmap/io/map_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cogmap/core/bresenham.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/gpkg.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/plan_files.h"
#include "cogmap/io/world_io.h"

namespace cogmap::io {

namespace {

// Colours per ASR (walls), cycling.
const Rgb kPalette[] = {{31, 119, 180}, {214, 39, 40}, {44, 160, 44}, {148, 103, 189}, {140, 86, 75},
                        {227, 119, 194}, {23, 190, 207}, {188, 189, 34}, {255, 127, 14}, {60, 60, 60}};
Rgb RoomColour(int id) { return kPalette[static_cast<unsigned>(id) % (sizeof(kPalette) / sizeof(kPalette[0]))]; }

std::string Hex(Rgb c) {
  char b[8];
  std::snprintf(b, sizeof(b), "#%02x%02x%02x", c.r, c.g, c.b);
  return b;
}

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof(b), "%.3f", v);
  return b;
}

const MasterRoom* FindRoom(const MasterMap& map, int id) {
  for (const auto& r : map.rooms)
    if (r.id == id) return &r;
  return nullptr;
}

std::vector<Vec2> Footprint(const MasterRoom& room) {
  std::vector<Vec2> pts = room.path;
  for (const auto& l : room.walls) pts.insert(pts.end(), l.begin(), l.end());
  return ConvexHull(std::move(pts));
}

}  // namespace

std::vector<Vec2> ConvexHull(std::vector<Vec2> p) {
  std::sort(p.begin(), p.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  p.erase(std::unique(p.begin(), p.end()), p.end());
  if (p.size() < 3) return p;
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Vec2> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

MasterMap BuildMasterMap(const std::vector<asr::Asr>& asrs, bool corrected) {
  MasterMap map;
  std::map<int, Pose2> correction;  // raw world -> map frame, per ASR
  for (const auto& a : asrs) {
    const Pose2 place = corrected ? a.world_from_local_corrected : a.world_from_local_raw;
    const Pose2 corr = place * a.world_from_local_raw.inverse();
    correction[a.id] = corr;
    MasterRoom room;
    room.id = a.id;
    room.walls = Transform(place, a.walls_local);
    Vec2 sum(0, 0);
    for (const auto& p : a.path) {
      room.path.push_back(corr * p.translation());
      sum += room.path.back();
    }
    room.label_m = room.path.empty() ? place.translation() : Vec2(sum / static_cast<double>(room.path.size()));
    map.rooms.push_back(std::move(room));
  }
  // Each exit once: keyed by its two ASRs (or by the leaving ASR and centre
  // when the far side is unknown).
  std::map<std::pair<int, int>, bool> seen;
  for (const auto& a : asrs) {
    for (const auto& e : a.exits) {
      const int from = e.from_asr >= 0 ? e.from_asr : a.id;
      if (e.to_asr >= 0 && seen.count({from, e.to_asr})) continue;
      if (e.to_asr >= 0) seen[{from, e.to_asr}] = true;
      const auto it = correction.find(from);
      MasterExit x;
      x.from_asr = from;
      x.to_asr = e.to_asr;
      x.center_m = it != correction.end() ? it->second * e.center_m : correction[a.id] * e.center_m;
      x.width_m = e.width_m;
      map.exits.push_back(x);
    }
  }
  double inf = std::numeric_limits<double>::infinity();
  Vec2 lo(inf, inf), hi(-inf, -inf);
  auto grow = [&](const Vec2& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& r : map.rooms) {
    for (const auto& l : r.walls)
      for (const auto& p : l) grow(p);
    for (const auto& p : r.path) grow(p);
  }
  for (const auto& e : map.exits) grow(e.center_m);
  if (lo.x() > hi.x()) lo = hi = Vec2(0, 0);
  map.min = lo;
  map.max = hi;
  return map;
}

std::string FormatMapSvg(const MasterMap& map, const MasterMapStyle& style) {
  const Vec2 lo = map.min - Vec2(style.margin_m, style.margin_m);
  const Vec2 hi = map.max + Vec2(style.margin_m, style.margin_m);
  const double w = hi.x() - lo.x(), h = hi.y() - lo.y();
  auto X = [&](const Vec2& p) { return Num(p.x() - lo.x()); };
  auto Y = [&](const Vec2& p) { return Num(hi.y() - p.y()); };
  std::ostringstream s;
  s << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << Num(w * style.px_per_m) << "\" height=\""
    << Num(h * style.px_per_m) << "\" viewBox=\"0 0 " << Num(w) << " " << Num(h) << "\">\n"
    << "<!-- cogmap master map: metres, map frame; origin of the view at (" << Num(lo.x()) << ", "
    << Num(hi.y()) << ") -->\n"
    << "<rect x=\"0\" y=\"0\" width=\"" << Num(w) << "\" height=\"" << Num(h) << "\" fill=\"white\"/>\n";
  if (style.path) {
    s << "<g id=\"path\" fill=\"none\" stroke=\"#bbbbbb\" stroke-width=\"0.04\">\n";
    for (const auto& r : map.rooms) {
      if (r.path.size() < 2) continue;
      s << "<polyline points=\"";
      for (const auto& p : r.path) s << X(p) << "," << Y(p) << " ";
      s << "\"/>\n";
    }
    s << "</g>\n";
  }
  s << "<g id=\"walls\" fill=\"none\" stroke-width=\"0.08\" stroke-linecap=\"round\" stroke-linejoin=\"round\">\n";
  for (const auto& r : map.rooms)
    for (const auto& l : r.walls) {
      if (l.size() < 2) continue;
      s << "<polyline data-asr=\"" << r.id << "\" stroke=\"" << Hex(RoomColour(r.id)) << "\" points=\"";
      for (const auto& p : l) s << X(p) << "," << Y(p) << " ";
      s << "\"/>\n";
    }
  s << "</g>\n";
  if (style.graph) {
    s << "<g id=\"graph\" stroke=\"#ff8800\" stroke-width=\"0.05\" stroke-dasharray=\"0.2,0.1\" fill=\"none\">\n";
    for (const auto& e : map.exits) {
      const MasterRoom* a = FindRoom(map, e.from_asr);
      const MasterRoom* b = FindRoom(map, e.to_asr);
      if (!a || !b) continue;
      s << "<polyline data-from=\"" << e.from_asr << "\" data-to=\"" << e.to_asr << "\" points=\"" << X(a->label_m)
        << "," << Y(a->label_m) << " " << X(e.center_m) << "," << Y(e.center_m) << " " << X(b->label_m) << ","
        << Y(b->label_m) << "\"/>\n";
    }
    s << "</g>\n";
  }
  s << "<g id=\"exits\" fill=\"#00aa00\">\n";
  for (const auto& e : map.exits)
    s << "<circle data-from=\"" << e.from_asr << "\" data-to=\"" << e.to_asr << "\" data-width=\""
      << Num(e.width_m) << "\" cx=\"" << X(e.center_m) << "\" cy=\"" << Y(e.center_m) << "\" r=\"0.15\"/>\n";
  s << "</g>\n";
  if (style.labels) {
    s << "<g id=\"labels\" font-family=\"sans-serif\" font-size=\"0.5\" text-anchor=\"middle\" fill=\"#000000\">\n";
    for (const auto& r : map.rooms)
      s << "<text data-asr=\"" << r.id << "\" x=\"" << X(r.label_m) << "\" y=\"" << Y(r.label_m) << "\">A" << r.id
        << "</text>\n";
    s << "</g>\n";
  }
  s << "</svg>\n";
  return s.str();
}

RgbImage RenderMap(const MasterMap& map, const MasterMapStyle& style) {
  const Vec2 lo = map.min - Vec2(style.margin_m, style.margin_m);
  const Vec2 hi = map.max + Vec2(style.margin_m, style.margin_m);
  const double k = style.px_per_m;
  const int width = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) * k)));
  const int height = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) * k)));
  RgbImage img(width, height);
  auto px = [&](const Vec2& p) { return Vec2((p.x() - lo.x()) * k, (hi.y() - p.y()) * k); };
  auto line = [&](const Vec2& a, const Vec2& b, Rgb c, int t) {
    const Vec2 pa = px(a), pb = px(b);
    img.DrawLine(pa.x(), pa.y(), pb.x(), pb.y(), c, t);
  };
  if (style.path)
    for (const auto& r : map.rooms)
      for (size_t i = 1; i < r.path.size(); ++i) line(r.path[i - 1], r.path[i], {190, 190, 190}, 1);
  for (const auto& r : map.rooms)
    for (const auto& l : r.walls)
      for (size_t i = 1; i < l.size(); ++i) line(l[i - 1], l[i], RoomColour(r.id), 2);
  if (style.graph)
    for (const auto& e : map.exits) {
      const MasterRoom* a = FindRoom(map, e.from_asr);
      const MasterRoom* b = FindRoom(map, e.to_asr);
      if (!a || !b) continue;
      line(a->label_m, e.center_m, {255, 136, 0}, 1);
      line(e.center_m, b->label_m, {255, 136, 0}, 1);
    }
  for (const auto& e : map.exits) {
    const Vec2 p = px(e.center_m);
    img.DrawDisc(p.x(), p.y(), std::max(2.0, 0.15 * k), {0, 170, 0});
  }
  if (style.labels)
    for (const auto& r : map.rooms) {
      const Vec2 p = px(r.label_m);
      const std::string text = "A" + std::to_string(r.id);
      const int scale = k >= 15 ? 2 : 1;
      img.DrawText(static_cast<int>(p.x()) - static_cast<int>(text.size()) * 3 * scale,
                   static_cast<int>(p.y()) - 4 * scale, text, {0, 0, 0}, scale);
    }
  return img;
}

grid::Grid2D<grid::CellClass> RasterizeMap(const MasterMap& map, double cell_m, double margin_m) {
  const Vec2 lo = map.min - Vec2(margin_m, margin_m);
  const Vec2 hi = map.max + Vec2(margin_m, margin_m);
  const int w = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell_m)));
  const int h = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell_m)));
  grid::Grid2D<grid::CellClass> g(grid::MapLimits(cell_m, lo, w, h), grid::CellClass::kUnknown);
  const auto& lim = g.limits();
  // Free: inside a room's footprint.
  for (const auto& r : map.rooms) {
    const auto hull = Footprint(r);
    if (hull.size() < 3) continue;
    Vec2 a = hull[0], b = hull[0];
    for (const auto& p : hull) {
      a = a.cwiseMin(p);
      b = b.cwiseMax(p);
    }
    const grid::CellIndex c0 = lim.CellOf(a), c1 = lim.CellOf(b);
    for (int y = std::max(0, c0.y()); y <= std::min(h - 1, c1.y()); ++y)
      for (int x = std::max(0, c0.x()); x <= std::min(w - 1, c1.x()); ++x) {
        const Vec2 c = lim.CenterOf({x, y});
        bool inside = true;
        for (size_t i = 0; i < hull.size() && inside; ++i) {
          const Vec2& p = hull[i];
          const Vec2& q = hull[(i + 1) % hull.size()];
          inside = (q.x() - p.x()) * (c.y() - p.y()) - (q.y() - p.y()) * (c.x() - p.x()) >= 0;
        }
        if (inside) g.at(x, y) = grid::CellClass::kEmpty;
      }
  }
  // Occupied: the walls.
  for (const auto& r : map.rooms)
    for (const auto& l : r.walls)
      for (size_t i = 1; i < l.size(); ++i) {
        const grid::CellIndex a = lim.CellOf(l[i - 1]), b = lim.CellOf(l[i]);
        WalkBresenham(a.x(), a.y(), b.x(), b.y(), [&](int x, int y) {
          if (lim.Contains({x, y})) g.at(x, y) = grid::CellClass::kOccupied;
          return true;
        });
      }
  return g;
}

std::string FormatMapGeoJson(const MasterMap& map) {
  using nlohmann::json;
  auto pt = [](const Vec2& p) { return json::array({p.x(), p.y()}); };
  // A line's coordinates without consecutive repeats; null when fewer than two
  // distinct points are left (no degenerate lines).
  auto line = [&](const std::vector<Vec2>& pts) -> json {
    json coords = json::array();
    const Vec2* last = nullptr;
    for (const auto& p : pts) {
      if (last && *last == p) continue;
      coords.push_back(pt(p));
      last = &p;
    }
    return coords.size() >= 2 ? coords : json();
  };
  json features = json::array();
  for (const auto& r : map.rooms) {
    for (const auto& l : r.walls) {
      const json coords = line(l);
      if (coords.is_null()) continue;
      features.push_back({{"type", "Feature"},
                          {"geometry", {{"type", "LineString"}, {"coordinates", coords}}},
                          {"properties", {{"kind", "wall"}, {"asr", r.id}}}});
    }
    const auto hull = Footprint(r);
    if (hull.size() >= 3) {
      json ring = json::array();
      for (const auto& p : hull) ring.push_back(pt(p));
      ring.push_back(pt(hull.front()));
      features.push_back({{"type", "Feature"},
                          {"geometry", {{"type", "Polygon"}, {"coordinates", json::array({ring})}}},
                          {"properties", {{"kind", "room"}, {"asr", r.id}, {"name", "A" + std::to_string(r.id)}}}});
    }
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Point"}, {"coordinates", pt(r.label_m)}}},
                        {"properties", {{"kind", "label"}, {"asr", r.id}, {"name", "A" + std::to_string(r.id)}}}});
    const json path = line(r.path);
    if (!path.is_null())
      features.push_back({{"type", "Feature"},
                          {"geometry", {{"type", "LineString"}, {"coordinates", path}}},
                          {"properties", {{"kind", "path"}, {"asr", r.id}}}});
  }
  for (const auto& e : map.exits)
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Point"}, {"coordinates", pt(e.center_m)}}},
                        {"properties", {{"kind", "exit"}, {"from", e.from_asr}, {"to", e.to_asr}, {"width_m", e.width_m}}}});
  // The legacy crs member names the engineering frame in metres (GDAL and
  // QGIS honour it instead of reading WGS 84 degrees; docs/map-files.md).
  json doc = {{"type", "FeatureCollection"},
              {"crs_note", "coordinates are metres in the cogmap map frame (x east, y north), not WGS84"},
              {"crs", {{"type", "name"}, {"properties", {{"name", MapFrameWkt()}}}}},
              {"features", features}};
  return doc.dump(1) + "\n";
}

FloorPlan MapFloorPlan(const MasterMap& map) {
  FloorPlan plan;
  for (const auto& r : map.rooms)
    for (const auto& l : r.walls)
      for (size_t i = 1; i < l.size(); ++i) plan.walls.push_back({l[i - 1], l[i]});
  plan.min = map.min;
  plan.max = map.max;
  return plan;
}

std::vector<std::string> WriteMasterMapFiles(const std::string& dir, const MasterMap& map,
                                             const MasterMapStyle& style, double raster_cell_m,
                                             const MasterMapOutputs& outputs) {
  const std::string base = (std::filesystem::path(dir) / "map").string();
  std::vector<std::string> written;
  if (outputs.svg) {
    WriteFileAtomically(base + ".svg", FormatMapSvg(map, style));
    written.push_back(base + ".svg");
  }
  if (outputs.png) {
    WritePng(base + ".png", RenderMap(map, style));
    written.push_back(base + ".png");
  }
  if (outputs.pgm) {
    WriteMapServer(base, RasterizeMap(map, raster_cell_m, style.margin_m));
    written.push_back(base + ".pgm");
    written.push_back(base + ".yaml");
  }
  if (outputs.geojson) {
    WriteFileAtomically(base + ".geojson", FormatMapGeoJson(map));
    written.push_back(base + ".geojson");
  }
  if (outputs.aria) {
    // Walls only, in a header that does not call them ground truth.
    plan::Plan walls;
    for (const auto& r : map.rooms)
      for (const auto& l : r.walls) walls.walls.push_back({l});
    walls.min = map.min;
    walls.max = map.max;
    WriteFileAtomically(base + ".map", FormatPlanAriaMap(walls));
    written.push_back(base + ".map");
  }
  return written;
}

}  // namespace cogmap::io
