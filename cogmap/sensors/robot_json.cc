#include "cogmap/sensors/robot_json.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"

namespace cogmap::sensors {
namespace {

using nlohmann::json;

void CheckKeys(const json& j, const std::set<std::string>& allowed, const std::string& src,
               const std::string& where) {
  if (!j.is_object()) throw InputError(src, 0, (where.empty() ? "robot" : where) + ": expected an object");
  for (const auto& [key, value] : j.items()) {
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError(src, 0, "unknown key '" + (where.empty() ? "" : where + ".") + key +
                                   "' (known: " + list + ")");
    }
  }
}

double Number(const json& j, const std::string& key, const std::string& src, const std::string& where) {
  const std::string name = where.empty() ? key : where + "." + key;
  if (!j.contains(key)) throw InputError(src, 0, name + ": missing");
  const json& v = j.at(key);
  if (!v.is_number()) throw InputError(src, 0, name + ": expected a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw InputError(src, 0, name + ": not a finite number");
  return d;
}

double NumberOr(const json& j, const std::string& key, double fallback, const std::string& src,
                const std::string& where) {
  return j.contains(key) ? Number(j, key, src, where) : fallback;
}

std::string StringOr(const json& j, const std::string& key, const std::string& fallback,
                     const std::string& src) {
  if (!j.contains(key)) return fallback;
  if (!j.at(key).is_string()) throw InputError(src, 0, key + ": expected a string");
  return j.at(key).get<std::string>();
}

RobotDescription ParseRobotJsonChecked(const json& j, const std::string& src);

}  // namespace

RobotDescription ParseRobotJson(const json& j, const std::string& src) {
  try {
    return ParseRobotJsonChecked(j, src);
  } catch (const json::exception& e) {  // a value of an unexpected type deep inside
    throw InputError(src, 0, std::string("invalid robot description: ") + e.what());
  }
}

namespace {
RobotDescription ParseRobotJsonChecked(const json& j, const std::string& src) {
  CheckKeys(j, {"name", "units", "angles", "radius", "sensors", "laser"}, src, "");
  RobotDescription r;
  r.name = StringOr(j, "name", "", src);
  if (r.name.empty()) throw InputError(src, 0, "name: missing or empty");
  const std::string units = StringOr(j, "units", "m", src);
  double len = 1.0;
  if (units == "mm") len = 0.001;
  else if (units != "m") throw InputError(src, 0, "units: expected \"m\" or \"mm\", got \"" + units + "\"");
  const std::string angles = StringOr(j, "angles", "deg", src);
  double ang = 1.0;
  if (angles == "deg") ang = kPi / 180.0;
  else if (angles != "rad") throw InputError(src, 0, "angles: expected \"deg\" or \"rad\", got \"" + angles + "\"");
  auto A = [&](double v) { return ang == 1.0 ? v : DegToRad(v); };

  r.radius_m = NumberOr(j, "radius", r.radius_m / len, src, "") * len;
  // Sizes a robot and its sensors can have (1e308 was taken): the grids,
  // the simulator and the boundary detector work in these lengths.
  if (!(r.radius_m > 0) || r.radius_m > 5.0) throw InputError(src, 0, "radius: must be in (0, 5] metres");

  if (j.contains("sensors")) {
    const json& ss = j.at("sensors");
    if (!ss.is_array()) throw InputError(src, 0, "sensors: expected an array");
    for (size_t i = 0; i < ss.size(); ++i) {
      const std::string w = "sensors[" + std::to_string(i) + "]";
      const json& s = ss[i];
      CheckKeys(s, {"x", "y", "heading", "beam_width", "min_range", "max_range", "kind"}, src, w);
      RangeSensor rs;
      rs.robot_from_sensor = {Number(s, "x", src, w) * len, Number(s, "y", src, w) * len,
                              A(Number(s, "heading", src, w))};
      if (s.contains("beam_width")) rs.beam_width_rad = A(Number(s, "beam_width", src, w));
      if (s.contains("min_range")) rs.min_range_m = Number(s, "min_range", src, w) * len;
      if (s.contains("max_range")) rs.max_range_m = Number(s, "max_range", src, w) * len;
      if (s.contains("kind")) {
        if (!s.at("kind").is_string()) throw InputError(src, 0, w + ".kind: expected a string");
        const std::string k = s.at("kind").get<std::string>();
        if (k == "sonar") rs.kind = SensorKind::kSonar;
        else if (k == "laser") rs.kind = SensorKind::kLaser;
        else throw InputError(src, 0, w + ".kind: expected \"sonar\" or \"laser\", got \"" + k + "\"");
      }
      if (!(rs.beam_width_rad > 0) || rs.beam_width_rad > 2 * kPi)
        throw InputError(src, 0, w + ".beam_width: must be in (0, 360] degrees");
      if (rs.min_range_m < 0) throw InputError(src, 0, w + ".min_range: must not be negative");
      if (!(rs.max_range_m > rs.min_range_m))
        throw InputError(src, 0, w + ".max_range: must exceed min_range");
      if (rs.max_range_m > 1000.0) throw InputError(src, 0, w + ".max_range: at most 1000 metres");
      if (rs.robot_from_sensor.translation().norm() > 10.0)
        throw InputError(src, 0, w + ": x, y must lie within 10 m of the robot's centre");
      r.sensors.push_back(rs);
    }
  }
  if (j.contains("laser")) {
    const json& l = j.at("laser");
    CheckKeys(l, {"beams", "fov", "max_range", "min_range"}, src, "laser");
    LaserOptions o;
    if (l.contains("beams")) {
      const double b = Number(l, "beams", src, "laser");
      if (b != std::floor(b) || b < 1 || b > 100000)
        throw InputError(src, 0, "laser.beams: expected a whole number in [1, 100000]");
      o.beams = static_cast<int>(b);
    }
    if (l.contains("fov")) o.fov_rad = A(Number(l, "fov", src, "laser"));
    if (l.contains("max_range")) o.max_range_m = Number(l, "max_range", src, "laser") * len;
    if (l.contains("min_range")) o.min_range_m = Number(l, "min_range", src, "laser") * len;
    if (o.max_range_m > 1000.0) throw InputError(src, 0, "laser.max_range: at most 1000 metres");
    RobotDescription laser;
    try {
      laser = MakeLaser(o, r.name);
    } catch (const InputError& e) {
      throw InputError(src, 0, e.what());
    }
    r.sensors.insert(r.sensors.end(), laser.sensors.begin(), laser.sensors.end());
  }
  if (r.sensors.empty()) throw InputError(src, 0, "no sensors: give \"sensors\" or \"laser\"");
  return r;
}
}  // namespace

RobotDescription LoadRobotJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open robot file");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::exception& e) {  // parse_error, out_of_range (a number like 1e999), ...
    throw InputError(path, 0, std::string("invalid JSON: ") + e.what());
  }
  return ParseRobotJson(j, path);
}

json RobotToJson(const RobotDescription& r, bool deg) {
  auto A = [&](double v) { return deg ? RadToDeg(v) : v; };
  json j;
  j["name"] = r.name;
  j["units"] = "m";
  j["angles"] = deg ? "deg" : "rad";
  j["radius"] = r.radius_m;
  json ss = json::array();
  for (const auto& s : r.sensors) {
    ss.push_back({{"x", s.robot_from_sensor.x},
                  {"y", s.robot_from_sensor.y},
                  {"heading", A(s.robot_from_sensor.theta)},
                  {"beam_width", A(s.beam_width_rad)},
                  {"min_range", s.min_range_m},
                  {"max_range", s.max_range_m},
                  {"kind", s.kind == SensorKind::kLaser ? "laser" : "sonar"}});
  }
  j["sensors"] = ss;
  return j;
}

RobotDescription ResolveRobot(const std::string& name_or_path) {
  for (const auto& n : BuiltinRobotNames())
    if (n == name_or_path) return BuiltinRobot(n);
  std::error_code ec;
  if (std::filesystem::is_regular_file(name_or_path, ec)) return LoadRobotJson(name_or_path);
  return BuiltinRobot(name_or_path);  // throws: unknown robot, listing the built-in ones
}

bool SameRobot(const RobotDescription& a, const RobotDescription& b) {
  if (a.name != b.name || a.radius_m != b.radius_m || a.sensors.size() != b.sensors.size()) return false;
  for (size_t i = 0; i < a.sensors.size(); ++i) {
    const auto& s = a.sensors[i];
    const auto& t = b.sensors[i];
    if (s.robot_from_sensor.x != t.robot_from_sensor.x || s.robot_from_sensor.y != t.robot_from_sensor.y ||
        s.robot_from_sensor.theta != t.robot_from_sensor.theta || s.beam_width_rad != t.beam_width_rad ||
        s.min_range_m != t.min_range_m || s.max_range_m != t.max_range_m || s.kind != t.kind)
      return false;
  }
  return true;
}

}  // namespace cogmap::sensors
