// The neutral ROS messages' helpers (ros_messages.h): compiled into cogmap_io
// and into the ROS 1 module (C++17, plugin_api.h), which decodes with them.
#include "cogmap/io/ros_messages.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace cogmap::io::ros {

MessageType TypeOf(const std::string& type_name) {
  std::string s = type_name;
  const auto msg = s.find("/msg/");
  if (msg != std::string::npos) s = s.substr(0, msg) + "/" + s.substr(msg + 5);
  if (s == "sensor_msgs/LaserScan") return MessageType::kLaserScan;
  if (s == "sensor_msgs/Range") return MessageType::kRange;
  if (s == "sensor_msgs/PointCloud") return MessageType::kPointCloud;
  if (s == "sensor_msgs/PointCloud2") return MessageType::kPointCloud2;
  if (s == "nav_msgs/Odometry") return MessageType::kOdometry;
  if (s == "tf2_msgs/TFMessage" || s == "tf/tfMessage") return MessageType::kTf;
  return MessageType::kOther;
}

std::string KnownTypesText() {
  return "sensor_msgs/LaserScan, sensor_msgs/Range, sensor_msgs/PointCloud, sensor_msgs/PointCloud2, "
         "nav_msgs/Odometry, tf2_msgs/TFMessage";
}

std::string DecodePointCloud2(const std::vector<PointField>& fields, bool big_endian, uint32_t point_step,
                              uint32_t width, uint32_t height, const uint8_t* data, size_t size,
                              std::vector<std::array<double, 3>>* points) {
  const PointField* xyz[3] = {nullptr, nullptr, nullptr};
  for (const auto& f : fields)
    for (int k = 0; k < 3; ++k)
      if (f.name == std::string(1, static_cast<char>('x' + k))) xyz[k] = &f;
  for (int k = 0; k < 3; ++k) {
    if (!xyz[k]) return std::string("PointCloud2 without a '") + static_cast<char>('x' + k) + "' field";
    if (xyz[k]->datatype != 7 && xyz[k]->datatype != 8)
      return std::string("PointCloud2 field '") + static_cast<char>('x' + k) + "' has datatype " +
             std::to_string(xyz[k]->datatype) + " (cogmap reads FLOAT32 = 7 and FLOAT64 = 8)";
  }
  const uint64_t n = uint64_t{width} * height;
  if (n > 0 && point_step == 0) return "PointCloud2 with point_step 0";
  if (n * point_step > size)
    return "PointCloud2 data holds " + std::to_string(size) + " bytes, " + std::to_string(n) + " points of " +
           std::to_string(point_step) + " bytes need " + std::to_string(n * point_step);
  const bool host_little = [] {
    const uint16_t one = 1;
    uint8_t b;
    std::memcpy(&b, &one, 1);
    return b == 1;
  }();
  const bool swap = big_endian == host_little;
  points->clear();
  points->reserve(n);
  for (uint64_t i = 0; i < n; ++i) {
    std::array<double, 3> p{};
    for (int k = 0; k < 3; ++k) {
      const size_t bytes = xyz[k]->datatype == 7 ? 4 : 8;
      const uint64_t at = i * point_step + xyz[k]->offset;
      if (at + bytes > size) return "PointCloud2 point " + std::to_string(i) + " runs past the data";
      uint8_t b[8];
      std::memcpy(b, data + at, bytes);
      if (swap) std::reverse(b, b + bytes);
      if (bytes == 4) {
        float f;
        std::memcpy(&f, b, 4);
        p[k] = f;
      } else {
        std::memcpy(&p[k], b, 8);
      }
    }
    points->push_back(p);
  }
  return "";
}

double YawOf(const Transform3& t) {
  return std::atan2(2.0 * (t.qw * t.qz + t.qx * t.qy), 1.0 - 2.0 * (t.qy * t.qy + t.qz * t.qz));
}

Transform3 FromPose2(double x, double y, double yaw_rad) {
  Transform3 t;
  t.x = x;
  t.y = y;
  t.qz = std::sin(yaw_rad / 2);
  t.qw = std::cos(yaw_rad / 2);
  return t;
}

}  // namespace cogmap::io::ros
