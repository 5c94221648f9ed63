#pragma once
// A log built in code for the job tests: a laser robot driving down a closed
// corridor (walls y = -1 and y = +1 for x in [0, 6], an end wall at x = 6),
// every range computed exactly, written as a native log.
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "cogmap/core/test_temp.h"
#include "cogmap/io/native_log.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::mapping::testing_util {

// 19 beams, 10 degrees apart from -90 to +90, 8 m range.
inline sensors::RobotDescription CorridorLaser() {
  sensors::LaserOptions o;
  o.beams = 19;
  o.max_range_m = 8.0;
  return sensors::MakeLaser(o, "corridor-laser");
}

// Range from 'p' along heading 'a' to the corridor's walls (max range when none is nearer).
inline double CorridorRange(const Pose2& p, double a, double max_range_m) {
  const double c = std::cos(a), s = std::sin(a);
  double best = max_range_m;
  if (std::abs(s) > 1e-12) {  // the side walls
    const double t = ((s > 0 ? 1.0 : -1.0) - p.y) / s;
    const double x = p.x + t * c;
    if (t > 0 && x >= 0.0 && x <= 6.0) best = std::min(best, t);
  }
  if (c > 1e-12) {  // the end wall
    const double t = (6.0 - p.x) / c;
    const double y = p.y + t * s;
    if (y >= -1.0 && y <= 1.0) best = std::min(best, t);
  }
  return best;
}

// 'n' records from x = 1 to x = 5 along y = 0, heading +x, truth = the true
// pose, odometry = the true pose shifted by 'odom_offset' (world frame).
inline std::vector<sensors::LogRecord> CorridorRecords(int n = 81, const Vec2& odom_offset = Vec2(0, 0)) {
  const sensors::RobotDescription robot = CorridorLaser();
  std::vector<sensors::LogRecord> out;
  for (int i = 0; i < n; ++i) {
    sensors::LogRecord r;
    r.time_s = 0.1 * i;
    const Pose2 truth{1.0 + 4.0 * i / (n - 1), 0.0, 0.0};
    r.truth = truth;
    r.odom = Pose2{truth.x + odom_offset.x(), truth.y + odom_offset.y(), 0.0};
    for (int k = 0; k < static_cast<int>(robot.sensors.size()); ++k) {
      const Pose2 s = sensors::SensorPose(truth, robot.sensors[k]);
      r.ranges.push_back({k, CorridorRange(s, s.theta, robot.sensors[k].max_range_m)});
    }
    out.push_back(r);
  }
  return out;
}

// The records as a native log in the test's temporary folder.
inline std::string WriteCorridorLog(const std::string& name, const std::vector<sensors::LogRecord>& records) {
  const std::string path = ::cogmap::testing_util::TestTempPath(name);
  std::ofstream out(path);
  io::NativeLogWriter w(out, CorridorLaser());
  for (const auto& r : records) w.Write(r);
  return path;
}

}  // namespace cogmap::mapping::testing_util
