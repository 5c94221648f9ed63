#include "cogmap/sensors/robot.h"

#include <algorithm>
#include <cmath>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"

namespace cogmap::sensors {
namespace {

struct MountMmDeg {
  double x_mm, y_mm, heading_deg;
};

// ARIA p3dx.p (SPEC 1): units 0-7 front, 8-15 rear.
constexpr MountMmDeg kP3dx[16] = {
    {69, 136, 90},     {114, 119, 50},    {148, 78, 30},     {166, 27, 10},
    {166, -27, -10},   {148, -78, -30},   {114, -119, -50},  {69, -136, -90},
    {-157, -136, -90}, {-203, -119, -130}, {-237, -78, -150}, {-255, -27, -170},
    {-255, 27, 170},   {-237, 78, 150},   {-203, 119, 130},  {-157, 136, 90}};

// ARIA p3at.p: the P2/P3-AT ring.
constexpr MountMmDeg kP3at[16] = {
    {147, 136, 90},    {193, 119, 50},    {227, 79, 30},     {245, 27, 10},
    {245, -27, -10},   {227, -79, -30},   {193, -119, -50},  {147, -136, -90},
    {-144, -136, -90}, {-189, -119, -130}, {-223, -79, -150}, {-241, -27, -170},
    {-241, 27, 170},   {-223, 79, 150},   {-189, 119, 130},  {-144, 136, 90}};

RangeSensor Sonar(const MountMmDeg& m) {
  RangeSensor s;
  s.robot_from_sensor = {m.x_mm / 1000.0, m.y_mm / 1000.0, DegToRad(m.heading_deg)};
  s.beam_width_rad = DegToRad(30.0);  // Polaroid 6500 main lobe (SPEC 6 sim default)
  s.min_range_m = 0.15;
  s.max_range_m = 5.0;  // Pioneer firmware reports 5000+ mm as no echo
  s.kind = SensorKind::kSonar;
  return s;
}

}  // namespace

RobotDescription MakeLaser(const LaserOptions& o, const std::string& name) {
  if (o.beams < 1) throw InputError("laser: beams must be at least 1, got " + std::to_string(o.beams));
  if (!(o.fov_rad > 0.0) || o.fov_rad > 2 * kPi)
    throw InputError("laser: field of view must be in (0, 360] degrees");
  if (!(o.max_range_m > o.min_range_m) || o.min_range_m < 0)
    throw InputError("laser: need 0 <= min_range < max_range");
  RobotDescription r;
  r.name = name;
  for (int i = 0; i < o.beams; ++i) {
    RangeSensor s;
    const double a = o.beams == 1 ? 0.0 : -o.fov_rad / 2 + o.fov_rad * i / (o.beams - 1);
    s.robot_from_sensor = {0.0, 0.0, a};
    s.beam_width_rad = o.beams == 1 ? DegToRad(0.5) : o.fov_rad / (o.beams - 1);
    s.min_range_m = o.min_range_m;
    s.max_range_m = o.max_range_m;
    s.kind = SensorKind::kLaser;
    r.sensors.push_back(s);
  }
  return r;
}

std::vector<std::string> BuiltinRobotNames() { return {"pioneer16", "pioneer8", "pioneer8-course", "p2at16", "laser"}; }

RobotDescription BuiltinRobot(const std::string& name, const LaserOptions& laser) {
  RobotDescription r;
  r.name = name;
  if (name == "pioneer16" || name == "pioneer8") {
    const int n = name == "pioneer16" ? 16 : 8;
    for (int i = 0; i < n; ++i) r.sensors.push_back(Sonar(kP3dx[i]));
    r.radius_m = 0.26;
    return r;
  }
  if (name == "pioneer8-course") {
    // The front ring with the headings that fit the real Pioneer log of
    // ../shared/data/pioneer-sonar-robond better than the stock ones (walls
    // straighter: line fraction 0.465 -> 0.544, entropy 0.349 -> 0.335 bits).
    constexpr double kCourseDeg[8] = {90, 37.5, 22.5, 7.5, -7.5, -22.5, -37.5, -90};
    for (int i = 0; i < 8; ++i) {
      MountMmDeg m = kP3dx[i];
      m.heading_deg = kCourseDeg[i];
      r.sensors.push_back(Sonar(m));
    }
    r.radius_m = 0.26;
    return r;
  }
  if (name == "p2at16") {
    for (const auto& m : kP3at) r.sensors.push_back(Sonar(m));
    r.radius_m = 0.32;
    return r;
  }
  if (name == "laser") return MakeLaser(laser, name);
  std::string known;
  for (const auto& k : BuiltinRobotNames()) known += (known.empty() ? "" : ", ") + k;
  throw InputError("unknown robot '" + name + "' (built in: " + known +
                   "; or give a robot JSON file)");
}

bool SeesOnlyForward(const RobotDescription& robot) {
  bool any = false;
  for (const auto& s : robot.sensors) {
    if (s.kind != SensorKind::kSonar) continue;
    any = true;
    // (A unit mounted square to the side, at exactly 90 degrees, looks ahead
    // as much as back.)
    if (std::abs(NormalizeAngle(s.robot_from_sensor.theta)) > 0.5 * kPi + 1e-6) return false;
  }
  return any;
}

double WidestBeamRad(const RobotDescription& robot) {
  double beam = 0.0;
  for (const auto& s : robot.sensors) beam = std::max(beam, s.beam_width_rad);
  return beam;
}

}  // namespace cogmap::sensors
