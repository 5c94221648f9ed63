#include "cogmap/io/plan_files.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/parallel.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/grid_io.h"

namespace cogmap::io {
namespace {

using json = nlohmann::ordered_json;

// WGS 84 ellipsoid.
constexpr double kWgs84A = 6378137.0;
constexpr double kWgs84F = 1.0 / 298.257223563;
constexpr double kWgs84E2 = kWgs84F * (2.0 - kWgs84F);

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

double RoundTo(double v, double step) { return std::round(v / step) * step; }

// Consecutive repeats removed (points closer than 'eps').
std::vector<Vec2> Dedupe(const std::vector<Vec2>& pts, double eps) {
  std::vector<Vec2> out;
  for (const Vec2& p : pts)
    if (out.empty() || (p - out.back()).norm() > eps) out.push_back(p);
  return out;
}

// A polygon ring fit to write: no repeats, not closed, counter-clockwise,
// >= 3 points and some area; empty when the room has no usable polygon.
std::vector<Vec2> CleanRing(const std::vector<Vec2>& polygon, double eps) {
  std::vector<Vec2> r = Dedupe(polygon, eps);
  while (r.size() > 1 && (r.front() - r.back()).norm() <= eps) r.pop_back();
  if (r.size() < 3) return {};
  const double area = SignedArea(r);
  if (std::abs(area) <= eps * eps) return {};
  if (area < 0) std::reverse(r.begin(), r.end());
  return r;
}

// Rooms and doors by id.
struct Index {
  std::map<int, const plan::Room*> rooms;
  std::map<int, const plan::Door*> doors;
  explicit Index(const plan::Plan& p) {
    for (const auto& r : p.rooms) rooms[r.id] = &r;
    for (const auto& d : p.doors) doors[d.id] = &d;
  }
  const plan::Room* room(int id) const {
    const auto it = rooms.find(id);
    return it == rooms.end() ? nullptr : it->second;
  }
  const plan::Door* door(int id) const {
    const auto it = doors.find(id);
    return it == doors.end() ? nullptr : it->second;
  }
};

std::string RoomName(const plan::Room& r) {
  return r.name.empty() ? (r.corridor ? "Corridor " : "Room ") + std::to_string(r.id) : r.name;
}

// The room graph edge's line: label of room a -> door centre -> label of room b.
std::vector<Vec2> EdgeLine(const Index& idx, const plan::Edge& e) {
  const plan::Room* a = idx.room(e.room_a);
  const plan::Room* b = idx.room(e.room_b);
  if (!a || !b) return {};
  std::vector<Vec2> line{a->label};
  if (const plan::Door* d = idx.door(e.door)) line.push_back(d->center());
  line.push_back(b->label);
  return line;
}

Vec2 PlanMin(const plan::Plan& p) { return p.min.cwiseMin(p.max); }
Vec2 PlanMax(const plan::Plan& p) { return p.min.cwiseMax(p.max); }

// Bounds of everything drawn (the plan's own when it has them).
void Bounds(const plan::Plan& p, Vec2* lo, Vec2* hi) {
  if (p.min != p.max) {
    *lo = PlanMin(p);
    *hi = PlanMax(p);
    return;
  }
  const double inf = std::numeric_limits<double>::infinity();
  Vec2 a(inf, inf), b(-inf, -inf);
  auto grow = [&](const Vec2& v) {
    a = a.cwiseMin(v);
    b = b.cwiseMax(v);
  };
  for (const auto& w : p.walls)
    for (const auto& v : w.points) grow(v);
  for (const auto& r : p.rooms)
    for (const auto& v : r.polygon) grow(v);
  for (const auto& d : p.doors) {
    grow(d.a);
    grow(d.b);
  }
  if (p.home) grow(p.home->translation());
  if (a.x() > b.x()) a = b = Vec2(0, 0);
  *lo = a;
  *hi = b;
}

// A FeatureCollection written to its stream as it is made: the collection's
// members on the first line, then one feature per line (compact, and a diff
// shows which features changed). No feature is held after it is written, so
// a big plan's file costs one feature's text, not the whole document.
class CollectionWriter {
 public:
  CollectionWriter(std::ostream& out, const json& head) : out_(out) {
    std::string text = head.dump();
    text.pop_back();  // the closing brace
    out_ << text << ",\"features\":[\n";
  }
  void Add(const json& feature) {
    if (count_++ > 0) out_ << ",\n";
    out_ << feature.dump();
  }
  void Close() { out_ << (count_ > 0 ? "\n" : "") << "]}\n"; }

 private:
  std::ostream& out_;
  size_t count_ = 0;
};

}  // namespace

double DominantWallDirection(const plan::Plan& plan) {
  // Mean of 4 phi over the wall segments, weighted by length: walls at right
  // angles vote for the same direction.
  double s = 0.0, c = 0.0;
  for (const auto& w : plan.walls)
    for (size_t i = 1; i < w.points.size(); ++i) {
      const Vec2 d = w.points[i] - w.points[i - 1];
      const double len = d.norm(), phi = std::atan2(d.y(), d.x());
      s += len * std::sin(4 * phi);
      c += len * std::cos(4 * phi);
    }
  return s == 0.0 && c == 0.0 ? 0.0 : 0.25 * std::atan2(s, c);
}

namespace {

}  // namespace

// ------------------------------------------------------------------ anchor

GeoAnchor ParseGeoAnchor(const std::string& text) {
  const std::string what = "--geo-anchor '" + text + "'";
  std::vector<std::string> fields;
  std::stringstream ss(text);
  std::string f;
  while (std::getline(ss, f, ',')) fields.push_back(Trim(f));
  if (!text.empty() && text.back() == ',') fields.push_back("");
  if (fields.size() != 3)
    throw InputError(what + ": expected LAT,LON,HEADING_DEG (three numbers separated by commas), got " +
                     std::to_string(fields.size()) + " field" + (fields.size() == 1 ? "" : "s"));
  const char* names[] = {"latitude", "longitude", "heading"};
  double v[3];
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = fields[i].empty() ? 0.0 : std::strtod(fields[i].c_str(), &end);
    if (fields[i].empty() || end != fields[i].c_str() + fields[i].size() || !std::isfinite(v[i]))
      throw InputError(what + ": " + names[i] + " '" + fields[i] + "' is not a number");
  }
  if (!(std::abs(v[0]) < 90.0))
    throw InputError(what + ": latitude " + fields[0] + " is outside (-90, 90) degrees (poles excluded)");
  if (!(std::abs(v[1]) <= 180.0))
    throw InputError(what + ": longitude " + fields[1] + " is outside [-180, 180] degrees");
  return {v[0], v[1], v[2]};
}

Vec2 LonLatOf(const GeoAnchor& anchor, const Vec2& map_m) {
  // Map frame -> east/north: +x has bearing h, +y bearing h - 90 deg.
  const double h = DegToRad(anchor.heading_deg);
  const double east = map_m.x() * std::sin(h) - map_m.y() * std::cos(h);
  const double north = map_m.x() * std::cos(h) + map_m.y() * std::sin(h);
  // East-north (up = 0) on the tangent plane -> ECEF -> geodetic.
  const double phi0 = DegToRad(anchor.lat_deg), lam0 = DegToRad(anchor.lon_deg);
  const double sp = std::sin(phi0), cp = std::cos(phi0), sl = std::sin(lam0), cl = std::cos(lam0);
  const double n0 = kWgs84A / std::sqrt(1.0 - kWgs84E2 * sp * sp);
  const double x = n0 * cp * cl - sl * east - sp * cl * north;
  const double y = n0 * cp * sl + cl * east - sp * sl * north;
  const double z = n0 * (1.0 - kWgs84E2) * sp + cp * north;
  const double p = std::hypot(x, y);
  double phi = std::atan2(z, p * (1.0 - kWgs84E2));
  for (int i = 0; i < 6; ++i) {
    const double s = std::sin(phi);
    const double n = kWgs84A / std::sqrt(1.0 - kWgs84E2 * s * s);
    const double height = p / std::cos(phi) - n;
    phi = std::atan2(z, p * (1.0 - kWgs84E2 * n / (n + height)));
  }
  return {RadToDeg(std::atan2(y, x)), RadToDeg(phi)};
}

// ------------------------------------------------------------------ GeoPackage

std::vector<GpkgLayer> PlanGpkgLayers(const plan::Plan& plan) {
  const Index idx(plan);
  constexpr double kEps = 1e-9;
  using T = GpkgFieldType;
  auto ids_text = [](const std::vector<int>& ids) {
    std::string s;
    for (size_t i = 0; i < ids.size(); ++i) s += (i ? "," : "") + std::to_string(ids[i]);
    return s;
  };
  std::vector<GpkgLayer> layers;

  GpkgLayer rooms{"rooms", "Rooms of the floor plan (polygons, map frame metres)", GpkgGeometryType::kPolygon,
                  {{"room_id", T::kInteger}, {"name", T::kText}, {"area_m2", T::kReal}, {"corridor", T::kBoolean},
                   {"doors", T::kText}, {"asr_ids", T::kText}, {"label_x", T::kReal}, {"label_y", T::kReal}},
                  {}};
  for (const auto& r : plan.rooms) {
    GpkgFeature f;
    f.geometry = {GpkgGeometryType::kPolygon, CleanRing(r.polygon, kEps)};
    f.values = {int64_t{r.id},        RoomName(r),     r.area_m2,       r.corridor,
                ids_text(r.doors), ids_text(r.asr_ids), r.label.x(), r.label.y()};
    rooms.features.push_back(std::move(f));
  }
  layers.push_back(std::move(rooms));

  GpkgLayer walls{"walls", "Wall faces of the floor plan (one per physical face)", GpkgGeometryType::kLineString,
                  {{"weight", T::kReal}, {"squared", T::kBoolean}, {"free_on_left", T::kBoolean},
                   {"two_sided", T::kBoolean}, {"length_m", T::kReal}, {"asr_ids", T::kText}},
                  {}};
  for (const auto& w : plan.walls) {
    const auto pts = Dedupe(w.points, kEps);
    if (pts.size() < 2) continue;  // no degenerate lines
    walls.features.push_back(
        {{GpkgGeometryType::kLineString, pts}, {w.weight, w.squared, w.free_on_left, w.two_sided, PolylineLength(pts), ids_text(w.asr_ids)}});
  }
  layers.push_back(std::move(walls));

  GpkgLayer doors{"doors", "Doors: the gap between the jambs", GpkgGeometryType::kLineString,
                  {{"door_id", T::kInteger}, {"width_m", T::kReal}, {"room_a", T::kInteger}, {"room_b", T::kInteger},
                   {"rooms", T::kText}, {"center_x", T::kReal}, {"center_y", T::kReal}},
                  {}};
  for (const auto& d : plan.doors) {
    auto room_value = [&](int id) -> GpkgValue { return id >= 0 ? GpkgValue{int64_t{id}} : GpkgValue{}; };
    std::string names;
    for (int id : {d.room_a, d.room_b})
      if (const plan::Room* r = idx.room(id)) names += (names.empty() ? "" : " | ") + RoomName(*r);
    GpkgFeature f;
    // A door whose jambs coincide has no line: its geometry is NULL (its
    // centre is still in center_x, center_y).
    if ((d.b - d.a).norm() > kEps) f.geometry = {GpkgGeometryType::kLineString, {d.a, d.b}};
    f.values = {int64_t{d.id}, d.width_m(), room_value(d.room_a), room_value(d.room_b), names,
                d.center().x(), d.center().y()};
    doors.features.push_back(std::move(f));
  }
  layers.push_back(std::move(doors));

  GpkgLayer graph{"room_graph", "Room graph: room label -> door -> room label", GpkgGeometryType::kLineString,
                  {{"room_a", T::kInteger}, {"room_b", T::kInteger}, {"door_id", T::kInteger},
                   {"name_a", T::kText}, {"name_b", T::kText}},
                  {}};
  for (const auto& e : plan.edges) {
    const auto line = Dedupe(EdgeLine(idx, e), kEps);
    if (line.size() < 2) continue;
    graph.features.push_back({{GpkgGeometryType::kLineString, line},
                              {int64_t{e.room_a}, int64_t{e.room_b},
                               e.door >= 0 ? GpkgValue{int64_t{e.door}} : GpkgValue{},
                               RoomName(*idx.room(e.room_a)), RoomName(*idx.room(e.room_b))}});
  }
  layers.push_back(std::move(graph));

  if (plan.home) {
    GpkgLayer home{"robot_home", "The robot's first pose", GpkgGeometryType::kPoint, {{"heading_deg", T::kReal}}, {}};
    home.features.push_back({{GpkgGeometryType::kPoint, {plan.home->translation()}},
                             {RadToDeg(NormalizeAngle(plan.home->theta))}});
    layers.push_back(std::move(home));
  }
  return layers;
}

// ------------------------------------------------------------------ GeoJSON

void WritePlanGeoJson(std::ostream& stream, const plan::Plan& plan, const std::optional<GeoAnchor>& anchor) {
  const Index idx(plan);
  json doc = {{"type", "FeatureCollection"}, {"name", "cogmap floor plan"}};
  if (anchor) {
    doc["cogmap"] = {{"coordinates", "WGS 84 longitude, latitude (degrees), RFC 7946"},
                     {"geo_anchor",
                      {{"lat_deg", anchor->lat_deg},
                       {"lon_deg", anchor->lon_deg},
                       {"heading_deg", anchor->heading_deg},
                       {"meaning", "map origin (0, 0) at lat, lon; the map's +x axis has this bearing, "
                                   "degrees clockwise from true north"}}}};
  } else {
    doc["cogmap"] = {{"coordinates", "local metres in the cogmap map frame (x, y), not WGS 84 degrees"},
                     {"units", "metre"},
                     {"frame", "the map frame: the robot's odometry frame at the start, as corrected"}};
    // The legacy (GeoJSON 2008) crs member: GDAL and QGIS read an engineering
    // system in metres instead of assuming WGS 84.
    doc["crs"] = {{"type", "name"}, {"properties", {{"name", MapFrameWkt()}}}};
  }
  CollectionWriter out(stream, doc);
  // Coordinates as written: mm in the map frame, or 1e-8 degree.
  auto place = [&](const Vec2& p) -> Vec2 {
    if (!anchor) return {RoundTo(p.x(), 1e-3), RoundTo(p.y(), 1e-3)};
    const Vec2 ll = LonLatOf(*anchor, p);
    return {RoundTo(ll.x(), 1e-8), RoundTo(ll.y(), 1e-8)};
  };
  auto coords = [&](const std::vector<Vec2>& pts) {
    std::vector<Vec2> placed;
    for (const Vec2& p : pts) placed.push_back(place(p));
    return Dedupe(placed, 0.0);
  };
  auto arr = [](const Vec2& p) { return json::array({p.x(), p.y()}); };
  auto line_json = [&](const std::vector<Vec2>& pts) {
    json c = json::array();
    for (const Vec2& p : pts) c.push_back(arr(p));
    return c;
  };
  auto feature = [](json geometry, json properties) {
    return json{{"type", "Feature"}, {"geometry", std::move(geometry)}, {"properties", std::move(properties)}};
  };
  auto mm = [](double v) { return RoundTo(v, 1e-3); };
  for (const auto& r : plan.rooms) {
    auto ring = coords(CleanRing(r.polygon, 1e-9));
    ring = CleanRing(ring, 0.0);  // rounding may have merged points
    json props = {{"layer", "rooms"}, {"room_id", r.id},     {"name", RoomName(r)},
                  {"area_m2", mm(r.area_m2)}, {"corridor", r.corridor}, {"doors", r.doors}};
    if (ring.empty()) continue;
    ring.push_back(ring.front());
    out.Add(feature({{"type", "Polygon"}, {"coordinates", json::array({line_json(ring)})}}, props));
  }
  for (const auto& w : plan.walls) {
    const auto pts = coords(w.points);
    if (pts.size() < 2) continue;
    out.Add(feature({{"type", "LineString"}, {"coordinates", line_json(pts)}},
                    {{"layer", "walls"},
                     {"weight", mm(w.weight)},
                     {"squared", w.squared},
                     {"free_on_left", w.free_on_left},
                     {"two_sided", w.two_sided},
                     {"length_m", mm(PolylineLength(w.points))}}));
  }
  for (const auto& d : plan.doors) {
    json rooms = json::array();
    for (int id : {d.room_a, d.room_b})
      if (const plan::Room* r = idx.room(id)) rooms.push_back(RoomName(*r));
    json props = {{"layer", "doors"}, {"door_id", d.id},     {"width_m", mm(d.width_m())},
                  {"room_a", d.room_a}, {"room_b", d.room_b}, {"rooms", rooms}};
    const auto pts = coords({d.a, d.b});
    if (pts.size() >= 2)
      out.Add(feature({{"type", "LineString"}, {"coordinates", line_json(pts)}}, props));
    else
      out.Add(feature({{"type", "Point"}, {"coordinates", arr(place(d.center()))}}, props));
  }
  for (const auto& e : plan.edges) {
    const auto pts = coords(EdgeLine(idx, e));
    if (pts.size() < 2) continue;
    out.Add(feature({{"type", "LineString"}, {"coordinates", line_json(pts)}},
                    {{"layer", "room_graph"},
                     {"room_a", e.room_a},
                     {"room_b", e.room_b},
                     {"door_id", e.door},
                     {"name_a", RoomName(*idx.room(e.room_a))},
                     {"name_b", RoomName(*idx.room(e.room_b))}}));
  }
  if (plan.home) {
    // The heading as a bearing (clockwise from north) when placed on the Earth.
    const double heading = anchor ? std::fmod(anchor->heading_deg - RadToDeg(plan.home->theta) + 720.0, 360.0)
                                  : RadToDeg(NormalizeAngle(plan.home->theta));
    out.Add(feature({{"type", "Point"}, {"coordinates", arr(place(plan.home->translation()))}},
                    {{"layer", "robot_home"}, {anchor ? "bearing_deg" : "heading_deg", RoundTo(heading, 0.1)}}));
  }
  out.Close();
}

std::string FormatPlanGeoJson(const plan::Plan& plan, const std::optional<GeoAnchor>& anchor) {
  std::ostringstream out;
  WritePlanGeoJson(out, plan, anchor);
  return out.str();
}

// ------------------------------------------------------------------ Nav2 route graph

void WriteRouteGraphGeoJson(std::ostream& stream, const plan::Plan& plan) {
  const Index idx(plan);
  json doc = {{"type", "FeatureCollection"},
              {"name", "cogmap room graph"},
              {"cogmap",
               {{"coordinates", "metres in the map frame (\"frame\": \"map\"), as the Nav2 Route Server reads them"},
                {"nodes", "rooms (at their label point) and doors (at their centre)"},
                {"edges", "directed, both ways, room -> door -> room through each doorway"}}},
              {"crs", {{"type", "name"}, {"properties", {{"name", MapFrameWkt()}}}}}};
  CollectionWriter out(stream, doc);
  std::map<int, unsigned> room_node, door_node;  // plan id -> node id
  unsigned next = 0;
  auto arr = [](const Vec2& p) { return json::array({RoundTo(p.x(), 1e-3), RoundTo(p.y(), 1e-3)}); };
  for (const auto& r : plan.rooms) {
    if (room_node.count(r.id)) continue;
    room_node[r.id] = next;
    out.Add(json{{"type", "Feature"},
                  {"geometry", {{"type", "Point"}, {"coordinates", arr(r.label)}}},
                  {"properties",
                   {{"id", next},
                    {"frame", "map"},
                    {"metadata", {{"kind", "room"}, {"room_id", r.id}, {"name", RoomName(r)}}}}}});
    ++next;
  }
  for (const auto& d : plan.doors) {
    if (door_node.count(d.id)) continue;
    door_node[d.id] = next;
    out.Add(json{{"type", "Feature"},
                  {"geometry", {{"type", "Point"}, {"coordinates", arr(d.center())}}},
                  {"properties",
                   {{"id", next},
                    {"frame", "map"},
                    {"metadata", {{"kind", "door"}, {"door_id", d.id}, {"width_m", RoundTo(d.width_m(), 1e-3)}}}}}});
    ++next;
  }
  // Undirected connections between nodes; each becomes two directed edges.
  std::set<std::pair<unsigned, unsigned>> links;
  std::vector<std::pair<unsigned, unsigned>> ordered;
  auto link = [&](unsigned a, unsigned b) {
    if (a == b || !links.insert({std::min(a, b), std::max(a, b)}).second) return;
    ordered.push_back({a, b});
  };
  auto room_of = [&](int id) { return room_node.find(id); };
  for (const auto& e : plan.edges) {
    const auto a = room_of(e.room_a), b = room_of(e.room_b);
    if (a == room_node.end() || b == room_node.end()) continue;
    const auto d = door_node.find(e.door);
    if (d == door_node.end()) {
      link(a->second, b->second);  // rooms joined without a door on record
    } else {
      link(a->second, d->second);
      link(d->second, b->second);
    }
  }
  // A door that leads to one known room only (an exit not yet explored).
  for (const auto& d : plan.doors)
    for (int r : {d.room_a, d.room_b}) {
      const auto it = room_of(r);
      if (it != room_node.end()) link(it->second, door_node[d.id]);
    }
  std::vector<Vec2> node_xy(next);
  for (const auto& r : plan.rooms) node_xy[room_node[r.id]] = r.label;
  for (const auto& d : plan.doors) node_xy[door_node[d.id]] = d.center();
  for (const auto& [a, b] : ordered)
    for (const auto& [s, t] : {std::pair{a, b}, std::pair{b, a}}) {
      out.Add(json{{"type", "Feature"},
                    {"geometry",
                     {{"type", "MultiLineString"},
                      {"coordinates", json::array({json::array({arr(node_xy[s]), arr(node_xy[t])})})}}},
                    {"properties", {{"id", next}, {"startid", s}, {"endid", t}}}});
      ++next;
    }
  out.Close();
}

std::string FormatRouteGraphGeoJson(const plan::Plan& plan) {
  std::ostringstream out;
  WriteRouteGraphGeoJson(out, plan);
  return out.str();
}

// ------------------------------------------------------------------ ARIA

void WritePlanAriaMap(std::ostream& out, const plan::Plan& plan) {
  auto mm = [](double m) { return std::llround(m * 1000.0); };
  // ARIA names may not hold '"', '#' or '%'.
  auto aria_name = [](std::string s) {
    for (char& c : s)
      if (c == '"' || c == '#' || c == '%' || c == '\n' || c == '\r') c = '_';
    return s;
  };
  std::vector<std::array<long long, 4>> lines;
  for (const auto& w : plan.walls)
    for (size_t i = 1; i < w.points.size(); ++i) {
      const std::array<long long, 4> l{mm(w.points[i - 1].x()), mm(w.points[i - 1].y()), mm(w.points[i].x()),
                                       mm(w.points[i].y())};
      if (l[0] != l[2] || l[1] != l[3]) lines.push_back(l);  // no zero-length lines
    }
  Vec2 lo, hi;
  Bounds(plan, &lo, &hi);
  out << "2D-Map\n";
  out << "LineMinPos: " << mm(lo.x()) << " " << mm(lo.y()) << "\n";
  out << "LineMaxPos: " << mm(hi.x()) << " " << mm(hi.y()) << "\n";
  out << "NumLines: " << lines.size() << "\n";
  out << "MapInfo: SectorType Name=Room \"Label=Room\" \"Desc=Room of the floor plan made by cogmap (the "
         "rectangle bounding its polygon along the building's walls)\" Shape=Plain\n";
  out << "MapInfo: BoundaryType Name=Doorway \"Label=Doorway\" \"Desc=Door of the floor plan made by cogmap (jamb "
         "to jamb)\"\n";
  // Angles are whole degrees (the 2D-Map grammar's Theta is an Integer).
  if (plan.home)
    out << "Cairn: RobotHome " << mm(plan.home->x) << " " << mm(plan.home->y) << " "
        << std::lround(RadToDeg(NormalizeAngle(plan.home->theta))) << " \"\" ICON \"Home\"\n";
  // ARIA sectors are rectangles, rotated by the cairn's theta about the map
  // origin: each room is the rectangle bounding its polygon in the frame of
  // the building's dominant wall direction.
  const long theta_deg = std::lround(RadToDeg(DominantWallDirection(plan)));
  const double theta = DegToRad(static_cast<double>(theta_deg));
  const Pose2 rotate{0, 0, theta};
  const Pose2 unrotate = rotate.inverse();
  for (const auto& r : plan.rooms) {
    if (r.polygon.empty()) continue;
    Vec2 a = unrotate * r.polygon.front(), b = a;
    for (const Vec2& p : r.polygon) {
      a = a.cwiseMin(unrotate * p);
      b = b.cwiseMax(unrotate * p);
    }
    const Vec2 c = rotate * Vec2(0.5 * (a + b));
    // Pose: the rectangle's centre (ARIA does not use it for sectors) and the rotation.
    out << "Cairn: Room " << mm(c.x()) << " " << mm(c.y()) << " " << theta_deg << " \"\" ICON \""
        << aria_name(RoomName(r)) << "\" " << mm(a.x()) << " " << mm(a.y()) << " " << mm(b.x()) << " " << mm(b.y())
        << "\n";
  }
  for (const auto& d : plan.doors) {
    const Vec2 c = d.center();
    out << "Cairn: Doorway " << mm(c.x()) << " " << mm(c.y()) << " 0 \"\" ICON \"door" << d.id << "\" "
        << mm(d.a.x()) << " " << mm(d.a.y()) << " " << mm(d.b.x()) << " " << mm(d.b.y()) << "\n";
  }
  out << "LINES\n";
  for (const auto& l : lines) out << l[0] << " " << l[1] << " " << l[2] << " " << l[3] << "\n";
  out << "DATA\n";
}

std::string FormatPlanAriaMap(const plan::Plan& plan) {
  std::ostringstream out;
  WritePlanAriaMap(out, plan);
  return out.str();
}

// ------------------------------------------------------------------ map_server

double PlanRasterCell(const plan::Plan& plan, const PlanFileOptions& o) {
  if (o.raster_cell_m > 0) return o.raster_cell_m;
  Vec2 lo, hi;
  Bounds(plan, &lo, &hi);
  const double w = hi.x() - lo.x() + 2 * o.raster_margin_m, h = hi.y() - lo.y() + 2 * o.raster_margin_m;
  double cell = std::max(o.raster_min_cell_m, std::sqrt(w * h / std::max(1.0, o.raster_max_pixels)));
  // Round up to whole millimetres, then grow until the image fits (the
  // ceil() of each side can add a row or column).
  cell = std::ceil(cell * 1000.0 - 1e-6) / 1000.0;
  while (std::ceil(w / cell) * std::ceil(h / cell) > o.raster_max_pixels) cell += 0.001;
  return cell;
}

grid::Grid2D<grid::CellClass> RasterizePlan(const plan::Plan& plan, double cell_m, double margin_m) {
  if (!(cell_m > 0)) throw InputError("map_server raster: the cell size must be positive");
  Vec2 lo, hi;
  Bounds(plan, &lo, &hi);
  lo -= Vec2(margin_m, margin_m);
  hi += Vec2(margin_m, margin_m);
  const int w = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell_m)));
  const int h = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell_m)));
  grid::Grid2D<grid::CellClass> g(grid::MapLimits(cell_m, lo, w, h), grid::CellClass::kUnknown);
  const auto& lim = g.limits();
  auto col = [&](double x) { return static_cast<int>(std::floor((x - lo.x()) / cell_m)); };
  auto row = [&](double y) { return static_cast<int>(std::floor((y - lo.y()) / cell_m)); };

  // Rooms: cells whose centre lies inside the polygon (even-odd scanlines).
  for (const auto& r : plan.rooms) {
    const auto ring = CleanRing(r.polygon, 1e-9);
    if (ring.empty()) continue;
    double y0 = ring[0].y(), y1 = ring[0].y();
    for (const Vec2& p : ring) {
      y0 = std::min(y0, p.y());
      y1 = std::max(y1, p.y());
    }
    std::vector<double> xs;
    for (int cy = std::max(0, row(y0)); cy <= std::min(h - 1, row(y1)); ++cy) {
      const double yc = lim.CenterOf({0, cy}).y();
      xs.clear();
      for (size_t i = 0; i < ring.size(); ++i) {
        const Vec2& p = ring[i];
        const Vec2& q = ring[(i + 1) % ring.size()];
        if ((p.y() <= yc) != (q.y() <= yc)) xs.push_back(p.x() + (yc - p.y()) / (q.y() - p.y()) * (q.x() - p.x()));
      }
      std::sort(xs.begin(), xs.end());
      for (size_t k = 0; k + 1 < xs.size(); k += 2) {
        // Cells whose centre x lies in [xs[k], xs[k+1]].
        const int c0 = std::max(0, static_cast<int>(std::ceil((xs[k] - lo.x()) / cell_m - 0.5)));
        const int c1 = std::min(w - 1, static_cast<int>(std::floor((xs[k + 1] - lo.x()) / cell_m - 0.5)));
        for (int cx = c0; cx <= c1; ++cx) g.at(cx, cy) = grid::CellClass::kEmpty;
      }
    }
  }

  // Every cell whose centre lies within 'radius' of [a, b] (and, for
  // 'along_trim' > 0, not within along_trim of either end) gets 'value'.
  auto band = [&](const Vec2& a, const Vec2& b, double radius, double along_trim, grid::CellClass value) {
    const Vec2 d = b - a;
    const double len = d.norm();
    const Vec2 u = len > 0 ? Vec2(d / len) : Vec2(1, 0);
    const Vec2 lo_p = a.cwiseMin(b) - Vec2(radius, radius), hi_p = a.cwiseMax(b) + Vec2(radius, radius);
    for (int cy = std::max(0, row(lo_p.y())); cy <= std::min(h - 1, row(hi_p.y())); ++cy)
      for (int cx = std::max(0, col(lo_p.x())); cx <= std::min(w - 1, col(hi_p.x())); ++cx) {
        const Vec2 c = lim.CenterOf({cx, cy});
        const double t = (c - a).dot(u);
        if (along_trim > 0 && (t < along_trim || t > len - along_trim)) continue;
        if (PointSegmentDistance(c, a, b) <= radius) g.at(cx, cy) = value;
      }
  };
  // Doors: a free band across the wall(s), short of the jambs.
  const double wall_radius = 0.71 * cell_m;
  for (const auto& d : plan.doors) {
    if (d.width_m() <= 2 * wall_radius) continue;
    band(d.a, d.b, std::max(0.3, 1.5 * cell_m), wall_radius, grid::CellClass::kEmpty);
  }
  // Walls last: occupied wherever a wall is, door bands included.
  for (const auto& wl : plan.walls)
    for (size_t i = 1; i < wl.points.size(); ++i)
      band(wl.points[i - 1], wl.points[i], wall_radius, 0.0, grid::CellClass::kOccupied);
  return g;
}

// ------------------------------------------------------------------ all files

std::vector<std::string> WritePlanFiles(const std::string& dir, const plan::Plan& plan,
                                        const PlanFileOptions& options) {
  const std::filesystem::path d(dir);
  std::vector<std::string> written;
  std::vector<std::function<void()>> write;  // one per file, each only reading the plan
  if (options.gpkg) {
    const std::string p = (d / "map.gpkg").string();
    write.push_back([&plan, p] { WriteGeoPackage(p, MapFrameSrs(), PlanGpkgLayers(plan)); });
    written.push_back(p);
  }
  if (options.geojson) {
    const std::string p = (d / "map.geojson").string();
    write.push_back([&plan, &options, p] {
      WriteFileAtomically(p, [&](std::ostream& out) { WritePlanGeoJson(out, plan, options.geo_anchor); });
    });
    written.push_back(p);
  }
  if (options.route_graph) {
    const std::string p = (d / "route_graph.geojson").string();
    write.push_back([&plan, p] { WriteFileAtomically(p, [&](std::ostream& out) { WriteRouteGraphGeoJson(out, plan); }); });
    written.push_back(p);
  }
  if (options.aria) {
    const std::string p = (d / "map.map").string();
    write.push_back([&plan, p] { WriteFileAtomically(p, [&](std::ostream& out) { WritePlanAriaMap(out, plan); }); });
    written.push_back(p);
  }
  if (options.map_server) {
    const std::string base = (d / "map").string();
    write.push_back([&plan, &options, base] {
      WriteMapServer(base, RasterizePlan(plan, PlanRasterCell(plan, options), options.raster_margin_m));
    });
    written.push_back(base + ".pgm");
    written.push_back(base + ".yaml");
  }
  ForEachShared(write.size(), options.threads, [&](size_t k) { write[k](); });
  return written;
}

}  // namespace cogmap::io
