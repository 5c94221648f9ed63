#include "cogmap/io/ros1_bag.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>

#include "cogmap/core/error.h"
#include "cogmap/io/ros_log.h"

namespace cogmap::io {
namespace {

namespace msg = cogmap::io::ros;  // the neutral messages; ::ros is ROS 1's namespace

msg::TransformStamped Stamped(int64_t ns, const std::string& parent, const std::string& child, double x, double y,
                             double yaw) {
  return {{ns, parent}, child, msg::FromPose2(x, y, yaw)};
}

msg::Odometry OdometryMsg(int64_t ns, const std::string& frame, const Pose2& p) {
  return {{ns, frame}, "base_link", msg::FromPose2(p.x, p.y, p.theta)};
}

}  // namespace

std::unique_ptr<LogReader> OpenRos1Bag(const std::string& path, const LogOpenOptions& options) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "cannot open: no such file");
  return msg::OpenBagLog(msg::OpenRos1BagSource(path), options);
}

long WriteRosAriaBag(const std::string& path, const sensors::RobotDescription& robot,
                     const std::function<bool(sensors::LogRecord*)>& next) {
  const auto fans = LaserFans(robot);
  std::vector<int> fan_of(robot.sensors.size(), -1);
  for (size_t f = 0; f < fans.size(); ++f)
    for (int k = 0; k < fans[f].count; ++k) fan_of[fans[f].first + k] = static_cast<int>(f);
  std::vector<int> sonars;
  for (size_t i = 0; i < robot.sensors.size(); ++i)
    if (robot.sensors[i].kind == sensors::SensorKind::kSonar) sonars.push_back(static_cast<int>(i));
  auto fan_name = [](size_t f, const std::string& base) { return f == 0 ? base : base + "_" + std::to_string(f + 1); };

  const std::string tmp = path + ".partial";
  long records = 0;
  try {
    msg::Ros1BagWriter bag(tmp);
    sensors::LogRecord r;
    while (next(&r)) {
      if (!(r.time_s >= 0) || !std::isfinite(r.time_s))
        throw InputError(path + ": record " + std::to_string(records + 1) + ": time " + std::to_string(r.time_s) +
                         " cannot be a ROS time (must be >= 0)");
      const int64_t ns = std::llround(r.time_s * 1e9);
      if (records == 0) {
        msg::TfMessage tf;
        if (!sonars.empty()) {
          tf.transforms.push_back(Stamped(ns, "base_link", "sonar", 0, 0, 0));
          for (size_t k = 0; k < sonars.size(); ++k) {
            const Pose2& p = robot.sensors[sonars[k]].robot_from_sensor;
            tf.transforms.push_back(Stamped(ns, "base_link", "sonar_" + std::to_string(k), p.x, p.y, p.theta));
          }
        }
        for (size_t f = 0; f < fans.size(); ++f) {
          const Pose2& p = robot.sensors[fans[f].first].robot_from_sensor;
          tf.transforms.push_back(Stamped(ns, "base_link", fan_name(f, "laser"), p.x, p.y, 0));
        }
        bag.Write("/tf_static", ns, tf);
      }
      bag.Write("/RosAria/pose", ns, OdometryMsg(ns, "odom", r.odom));
      msg::TfMessage tf;
      tf.transforms.push_back(Stamped(ns, "odom", "base_link", r.odom.x, r.odom.y, r.odom.theta));
      bag.Write("/tf", ns, tf);
      if (r.truth) bag.Write("/base_pose_ground_truth", ns, OdometryMsg(ns, "map", *r.truth));
      if (!r.ranges.empty()) {
        msg::PointCloud cloud;
        std::vector<msg::LaserScan> scans(fans.size());
        std::vector<bool> used(fans.size(), false);
        for (const auto& q : r.ranges) {
          if (q.sensor < 0 || q.sensor >= static_cast<int>(robot.sensors.size()))
            throw InputError(path + ": record " + std::to_string(records + 1) + ": reading of sensor " +
                             std::to_string(q.sensor) + " but robot '" + robot.name + "' has " +
                             std::to_string(robot.sensors.size()) + " sensors");
          const auto& s = robot.sensors[q.sensor];
          if (s.kind == sensors::SensorKind::kSonar) {
            const Pose2& p = s.robot_from_sensor;
            cloud.points.push_back({p.x + q.range_m * std::cos(p.theta), p.y + q.range_m * std::sin(p.theta), 0.0});
            continue;
          }
          const int f = fan_of[q.sensor];
          auto& scan = scans[f];
          if (!used[f]) {
            used[f] = true;
            const LaserFan& fan = fans[f];
            scan.header = {ns, fan_name(f, "laser")};
            scan.angle_min_rad = fan.angle_min_rad;
            scan.angle_increment_rad = fan.increment_rad;
            scan.range_min_m = robot.sensors[fan.first].min_range_m;
            scan.range_max_m = robot.sensors[fan.first].max_range_m;
            scan.ranges.assign(fan.count, std::numeric_limits<float>::quiet_NaN());
          }
          scan.ranges[q.sensor - fans[f].first] = static_cast<float>(q.range_m);
        }
        if (!cloud.points.empty()) {
          cloud.header = {ns, "sonar"};
          bag.Write("/RosAria/sonar", ns, cloud);
        }
        for (size_t f = 0; f < fans.size(); ++f)
          if (used[f]) bag.Write(fan_name(f, "/scan"), ns, scans[f]);
      }
      ++records;
    }
    bag.Close();
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot write (" + ec.message() + ")");
  }
  return records;
}

}  // namespace cogmap::io
