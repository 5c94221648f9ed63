#include "cogmap/io/map_files.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "cogmap/core/bresenham.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/gpkg.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/io/plan_files.h"
#include "cogmap/io/world_io.h"

namespace cogmap::io {

namespace {

std::vector<Vec2> Footprint(const MasterRoom& room) {
  std::vector<Vec2> pts = room.path;
  for (const auto& l : room.walls) pts.insert(pts.end(), l.begin(), l.end());
  return ConvexHull(std::move(pts));
}

}  // namespace

MasterMap BuildMasterMap(const std::vector<asr::Asr>& asrs, bool corrected,
                         std::map<int, std::vector<Pose2>>* placed_paths) {
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
    std::vector<Pose2>* placed = nullptr;
    if (placed_paths && corrected)
      if (auto it = placed_paths->find(a.id); it != placed_paths->end() && !it->second.empty()) placed = &it->second;
    if (placed) {
      for (const auto& p : *placed) {
        room.path.push_back(p.translation());
        sum += room.path.back();
      }
      std::vector<Pose2>().swap(*placed);
    } else {
      for (const auto& p : a.path) {
        room.path.push_back(corr * p.translation());
        sum += room.path.back();
      }
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
      for (const auto& l : r.walls) {
        plan::Wall w;
        w.points = l;
        walls.walls.push_back(std::move(w));
      }
    walls.min = map.min;
    walls.max = map.max;
    WriteFileAtomically(base + ".map", FormatPlanAriaMap(walls));
    written.push_back(base + ".map");
  }
  return written;
}

}  // namespace cogmap::io
