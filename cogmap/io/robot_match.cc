// Robot geometry helpers of log_reader.h (MatchingBuiltinRobot, LaserFans):
// compiled into cogmap_io and into the MRPT module (plugin_api.h).
#include <cmath>

#include "cogmap/core/angles.h"
#include "cogmap/io/log_reader.h"

namespace cogmap::io {

std::optional<sensors::RobotDescription> MatchingBuiltinRobot(const sensors::RobotDescription& robot,
                                                              double tolerance) {
  auto near = [&](double a, double b) { return std::abs(a - b) <= tolerance; };
  for (const auto& name : sensors::BuiltinRobotNames()) {
    sensors::RobotDescription b = sensors::BuiltinRobot(name);
    if (b.sensors.size() != robot.sensors.size()) continue;
    bool same = true;
    for (size_t i = 0; same && i < b.sensors.size(); ++i) {
      const auto &p = b.sensors[i], &q = robot.sensors[i];
      same = near(p.robot_from_sensor.x, q.robot_from_sensor.x) && near(p.robot_from_sensor.y, q.robot_from_sensor.y) &&
             near(NormalizeAngle(p.robot_from_sensor.theta - q.robot_from_sensor.theta), 0.0) &&
             near(p.beam_width_rad, q.beam_width_rad) && near(p.min_range_m, q.min_range_m) &&
             near(p.max_range_m, q.max_range_m) && p.kind == q.kind;
    }
    if (same) return b;
  }
  return std::nullopt;
}

std::vector<LaserFan> LaserFans(const sensors::RobotDescription& robot) {
  std::vector<LaserFan> fans;
  const auto& s = robot.sensors;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i].kind != sensors::SensorKind::kLaser) continue;
    if (!fans.empty()) {
      LaserFan& f = fans.back();
      const auto& a = s[f.first];
      const size_t last = f.first + f.count - 1;
      const bool same_place = last + 1 == i && s[i].robot_from_sensor.x == a.robot_from_sensor.x &&
                              s[i].robot_from_sensor.y == a.robot_from_sensor.y &&
                              s[i].max_range_m == a.max_range_m && s[i].min_range_m == a.min_range_m;
      const double step = NormalizeAngle(s[i].robot_from_sensor.theta - s[last].robot_from_sensor.theta);
      if (same_place && (f.count == 1 || std::abs(step - f.increment_rad) < 1e-9)) {
        if (f.count == 1) f.increment_rad = step;
        ++f.count;
        continue;
      }
    }
    fans.push_back({static_cast<int>(i), 1, s[i].robot_from_sensor.theta, 0.0});
  }
  return fans;
}

}  // namespace cogmap::io
