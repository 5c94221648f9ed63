#include "cogmap/plan/plan_json.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <ostream>
#include <sstream>

#include "cogmap/core/error.h"

namespace cogmap::plan {
namespace {

using nlohmann::json;

json Pt(const Vec2& p) { return json::array({p.x(), p.y()}); }

// Reading with the path of each value for the error message.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}
  [[noreturn]] void Fail(const std::string& where, const std::string& problem) const {
    throw InputError(source_, 0, where + ": " + problem);
  }
  const json& Field(const json& obj, const std::string& where, const char* key) const {
    if (!obj.is_object()) Fail(where, "expected an object");
    auto it = obj.find(key);
    if (it == obj.end()) Fail(where, std::string("missing \"") + key + "\"");
    return *it;
  }
  double Number(const json& v, const std::string& where) const {
    if (!v.is_number()) Fail(where, "expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) Fail(where, "not a finite number");
    return d;
  }
  int Int(const json& v, const std::string& where) const {
    if (!v.is_number_integer()) Fail(where, "expected an integer");
    const auto i = v.get<int64_t>();
    if (i < -1000000000LL || i > 1000000000LL) Fail(where, "integer out of range");
    return static_cast<int>(i);
  }
  bool Bool(const json& v, const std::string& where) const {
    if (!v.is_boolean()) Fail(where, "expected true or false");
    return v.get<bool>();
  }
  std::string String(const json& v, const std::string& where) const {
    if (!v.is_string()) Fail(where, "expected a string");
    return v.get<std::string>();
  }
  const json& Array(const json& v, const std::string& where) const {
    if (!v.is_array()) Fail(where, "expected an array");
    return v;
  }
  Vec2 Point(const json& v, const std::string& where) const {
    if (!v.is_array() || v.size() != 2) Fail(where, "expected a point [x, y]");
    return Vec2(Number(v[0], where + "[0]"), Number(v[1], where + "[1]"));
  }
  std::vector<Vec2> Points(const json& v, const std::string& where) const {
    std::vector<Vec2> out;
    Array(v, where);
    for (size_t i = 0; i < v.size(); ++i) out.push_back(Point(v[i], where + "[" + std::to_string(i) + "]"));
    return out;
  }
  std::vector<int> Ints(const json& v, const std::string& where) const {
    std::vector<int> out;
    Array(v, where);
    for (size_t i = 0; i < v.size(); ++i) out.push_back(Int(v[i], where + "[" + std::to_string(i) + "]"));
    return out;
  }

 private:
  std::string source_;
};

}  // namespace

namespace {

json WallJson(const Wall& w) {
  json pts = json::array();
  for (const Vec2& p : w.points) pts.push_back(Pt(p));
  return {{"points", pts}, {"free_on_left", w.free_on_left}, {"two_sided", w.two_sided},
          {"weight", w.weight}, {"asr_ids", w.asr_ids}, {"squared", w.squared}};
}

json DoorJson(const Door& d) {
  return {{"id", d.id}, {"a", Pt(d.a)}, {"b", Pt(d.b)}, {"room_a", d.room_a}, {"room_b", d.room_b},
          {"from_asr", d.from_asr}, {"to_asr", d.to_asr}};
}

json RoomJson(const Room& r) {
  json poly = json::array();
  for (const Vec2& p : r.polygon) poly.push_back(Pt(p));
  return {{"id", r.id}, {"name", r.name}, {"corridor", r.corridor}, {"polygon", poly},
          {"area_m2", r.area_m2}, {"label", Pt(r.label)}, {"doors", r.doors}, {"asr_ids", r.asr_ids},
          {"graph_rooms", r.graph_rooms}};
}

json EdgeJson(const Edge& e) { return {{"room_a", e.room_a}, {"room_b", e.room_b}, {"door", e.door}}; }

// The plan's members but its four lists (walls, doors, rooms, edges).
json HeadJson(const Plan& plan) {
  json j;
  j["format"] = kPlanFormat;
  j["version"] = kPlanFormatVersion;
  j["frame"] = "map: metres, x east, y north (the corrected odometry frame of the run)";
  j["dominant_direction_rad"] = plan.dominant_direction_rad;
  j["direction_scatter_rad"] = plan.direction_scatter_rad;
  if (plan.home) j["home"] = {{"x", plan.home->x}, {"y", plan.home->y}, {"theta", plan.home->theta}};
  else j["home"] = nullptr;
  j["bounds"] = {{"min", Pt(plan.min)}, {"max", Pt(plan.max)}};
  return j;
}

// 'text' (a value as dump(2) prints it at the top level) as it stands at
// 'depth' in an indented document: every line after the first indented by
// two spaces per level. JSON strings hold no raw newline, so every newline
// in the text is the layout's.
void PutIndented(std::ostream& out, const std::string& text, int depth) {
  const std::string pad(2 * static_cast<size_t>(depth), ' ');
  size_t start = 0;
  for (size_t nl; (nl = text.find('\n', start)) != std::string::npos; start = nl + 1) {
    out.write(text.data() + start, static_cast<std::streamsize>(nl + 1 - start));
    out << pad;
  }
  out.write(text.data() + start, static_cast<std::streamsize>(text.size() - start));
}

// One list of the plan as dump(2) prints it at depth 1, element by element.
template <class T, class F>
void PutList(std::ostream& out, const std::vector<T>& items, F&& to_json) {
  if (items.empty()) {
    out << "[]";
    return;
  }
  out << "[\n";
  for (size_t i = 0; i < items.size(); ++i) {
    out << "    ";
    PutIndented(out, to_json(items[i]).dump(2), 2);
    out << (i + 1 < items.size() ? ",\n" : "\n");
  }
  out << "  ]";
}

}  // namespace

json PlanToJson(const Plan& plan) {
  json j = HeadJson(plan);
  json walls = json::array();
  for (const Wall& w : plan.walls) walls.push_back(WallJson(w));
  j["walls"] = walls;
  json doors = json::array();
  for (const Door& d : plan.doors) doors.push_back(DoorJson(d));
  j["doors"] = doors;
  json rooms = json::array();
  for (const Room& r : plan.rooms) rooms.push_back(RoomJson(r));
  j["rooms"] = rooms;
  json edges = json::array();
  for (const Edge& e : plan.edges) edges.push_back(EdgeJson(e));
  j["edges"] = edges;
  return j;
}

void WritePlanJson(std::ostream& out, const Plan& plan) {
  // The members in the order json's sorted object prints them, each list
  // written one element at a time: the text of PlanToJson(plan).dump(2).
  const json head = HeadJson(plan);
  std::map<std::string, std::function<void()>> members;
  for (auto it = head.begin(); it != head.end(); ++it)
    members[it.key()] = [&out, value = &*it] { PutIndented(out, value->dump(2), 1); };
  members["walls"] = [&] { PutList(out, plan.walls, WallJson); };
  members["doors"] = [&] { PutList(out, plan.doors, DoorJson); };
  members["rooms"] = [&] { PutList(out, plan.rooms, RoomJson); };
  members["edges"] = [&] { PutList(out, plan.edges, EdgeJson); };
  out << "{\n";
  size_t i = 0;
  for (const auto& [key, put] : members) {
    out << "  " << json(key).dump() << ": ";
    put();
    out << (++i < members.size() ? ",\n" : "\n");
  }
  out << "}\n";
}

std::string PlanToJsonText(const Plan& plan) {
  std::ostringstream out;
  WritePlanJson(out, plan);
  return out.str();
}

Plan PlanFromJson(const json& j, const std::string& source) {
  const Reader rd(source);
  if (!j.is_object()) rd.Fail("top level", "expected a JSON object");
  if (rd.String(rd.Field(j, "top level", "format"), "format") != kPlanFormat)
    rd.Fail("format", std::string("expected \"") + kPlanFormat + "\"");
  const int version = rd.Int(rd.Field(j, "top level", "version"), "version");
  if (version != kPlanFormatVersion)
    rd.Fail("version", std::to_string(version) + " is not supported (this cogmap reads " +
                           std::to_string(kPlanFormatVersion) + ")");
  Plan plan;
  plan.dominant_direction_rad = rd.Number(rd.Field(j, "top level", "dominant_direction_rad"), "dominant_direction_rad");
  if (j.contains("direction_scatter_rad"))
    plan.direction_scatter_rad = rd.Number(j["direction_scatter_rad"], "direction_scatter_rad");
  const json& home = rd.Field(j, "top level", "home");
  if (!home.is_null())
    plan.home = Pose2{rd.Number(rd.Field(home, "home", "x"), "home.x"), rd.Number(rd.Field(home, "home", "y"), "home.y"),
                      rd.Number(rd.Field(home, "home", "theta"), "home.theta")};
  const json& bounds = rd.Field(j, "top level", "bounds");
  plan.min = rd.Point(rd.Field(bounds, "bounds", "min"), "bounds.min");
  plan.max = rd.Point(rd.Field(bounds, "bounds", "max"), "bounds.max");

  const json& walls = rd.Array(rd.Field(j, "top level", "walls"), "walls");
  for (size_t i = 0; i < walls.size(); ++i) {
    const std::string at = "walls[" + std::to_string(i) + "]";
    Wall w;
    w.points = rd.Points(rd.Field(walls[i], at, "points"), at + ".points");
    if (w.points.size() < 2) rd.Fail(at + ".points", "a wall needs at least 2 points");
    w.free_on_left = rd.Bool(rd.Field(walls[i], at, "free_on_left"), at + ".free_on_left");
    w.two_sided = rd.Bool(rd.Field(walls[i], at, "two_sided"), at + ".two_sided");
    w.weight = rd.Number(rd.Field(walls[i], at, "weight"), at + ".weight");
    w.asr_ids = rd.Ints(rd.Field(walls[i], at, "asr_ids"), at + ".asr_ids");
    w.squared = rd.Bool(rd.Field(walls[i], at, "squared"), at + ".squared");
    plan.walls.push_back(std::move(w));
  }
  const json& rooms = rd.Array(rd.Field(j, "top level", "rooms"), "rooms");
  for (size_t i = 0; i < rooms.size(); ++i) {
    const std::string at = "rooms[" + std::to_string(i) + "]";
    Room r;
    r.id = rd.Int(rd.Field(rooms[i], at, "id"), at + ".id");
    if (r.id != static_cast<int>(i)) rd.Fail(at + ".id", "expected " + std::to_string(i) + " (rooms are numbered in order)");
    r.name = rd.String(rd.Field(rooms[i], at, "name"), at + ".name");
    r.corridor = rd.Bool(rd.Field(rooms[i], at, "corridor"), at + ".corridor");
    r.polygon = rd.Points(rd.Field(rooms[i], at, "polygon"), at + ".polygon");
    if (r.polygon.size() < 3) rd.Fail(at + ".polygon", "a room polygon needs at least 3 points");
    r.area_m2 = rd.Number(rd.Field(rooms[i], at, "area_m2"), at + ".area_m2");
    r.label = rd.Point(rd.Field(rooms[i], at, "label"), at + ".label");
    r.doors = rd.Ints(rd.Field(rooms[i], at, "doors"), at + ".doors");
    r.asr_ids = rd.Ints(rd.Field(rooms[i], at, "asr_ids"), at + ".asr_ids");
    r.graph_rooms = rd.Ints(rd.Field(rooms[i], at, "graph_rooms"), at + ".graph_rooms");
    plan.rooms.push_back(std::move(r));
  }
  const int n_rooms = static_cast<int>(plan.rooms.size());
  auto room_ok = [&](int r) { return r >= -1 && r < n_rooms; };
  const json& doors = rd.Array(rd.Field(j, "top level", "doors"), "doors");
  for (size_t i = 0; i < doors.size(); ++i) {
    const std::string at = "doors[" + std::to_string(i) + "]";
    Door d;
    d.id = rd.Int(rd.Field(doors[i], at, "id"), at + ".id");
    if (d.id != static_cast<int>(i)) rd.Fail(at + ".id", "expected " + std::to_string(i) + " (doors are numbered in order)");
    d.a = rd.Point(rd.Field(doors[i], at, "a"), at + ".a");
    d.b = rd.Point(rd.Field(doors[i], at, "b"), at + ".b");
    d.room_a = rd.Int(rd.Field(doors[i], at, "room_a"), at + ".room_a");
    d.room_b = rd.Int(rd.Field(doors[i], at, "room_b"), at + ".room_b");
    if (!room_ok(d.room_a)) rd.Fail(at + ".room_a", "no room " + std::to_string(d.room_a));
    if (!room_ok(d.room_b)) rd.Fail(at + ".room_b", "no room " + std::to_string(d.room_b));
    d.from_asr = rd.Int(rd.Field(doors[i], at, "from_asr"), at + ".from_asr");
    d.to_asr = rd.Int(rd.Field(doors[i], at, "to_asr"), at + ".to_asr");
    plan.doors.push_back(d);
  }
  const int n_doors = static_cast<int>(plan.doors.size());
  for (const Room& r : plan.rooms)
    for (int d : r.doors)
      if (d < 0 || d >= n_doors) rd.Fail("rooms[" + std::to_string(r.id) + "].doors", "no door " + std::to_string(d));
  const json& edges = rd.Array(rd.Field(j, "top level", "edges"), "edges");
  for (size_t i = 0; i < edges.size(); ++i) {
    const std::string at = "edges[" + std::to_string(i) + "]";
    Edge e;
    e.room_a = rd.Int(rd.Field(edges[i], at, "room_a"), at + ".room_a");
    e.room_b = rd.Int(rd.Field(edges[i], at, "room_b"), at + ".room_b");
    e.door = rd.Int(rd.Field(edges[i], at, "door"), at + ".door");
    if (e.room_a < 0 || e.room_a >= n_rooms) rd.Fail(at + ".room_a", "no room " + std::to_string(e.room_a));
    if (e.room_b < 0 || e.room_b >= n_rooms) rd.Fail(at + ".room_b", "no room " + std::to_string(e.room_b));
    if (e.door < 0 || e.door >= n_doors) rd.Fail(at + ".door", "no door " + std::to_string(e.door));
    plan.edges.push_back(e);
  }
  return plan;
}

Plan ParsePlanJson(const std::string& text, const std::string& source) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError(source, 0, std::string("not valid JSON (") + e.what() + ")");
  }
  return PlanFromJson(j, source);
}

Plan ReadPlanJson(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "cannot be read");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "read error");
  return ParsePlanJson(ss.str(), path);
}

}  // namespace cogmap::plan
