#pragma once
// Bags for the ROS 1 reader's tests, written by rosbag from messages built in
// the tests (the writer is compiled as C++17, as the ROS 1 headers need).
#include <cstdint>
#include <string>
#include <vector>

namespace cogmap::io::testing_util {

struct FixtureMessage {
  enum Kind { kOdometry, kLaserScan, kRange, kPointCloud2, kTf, kString };
  std::string topic;
  int64_t time_ns = 0;  // bag time and header stamp
  Kind kind = kOdometry;
  std::string frame, child;  // header.frame_id; child_frame_id (odometry, tf)
  double x = 0, y = 0, yaw = 0;  // odometry pose; tf: one transform parent 'frame' -> 'child'
  double angle_min = 0, angle_increment = 0, range_min = 0, range_max = 0, field_of_view = 0;
  std::vector<float> values;  // LaserScan ranges; Range: {range}; PointCloud2: x y z per point (FLOAT32)
};

// Writes the messages in order to a new bag at 'path'.
void WriteFixtureBag(const std::string& path, const std::vector<FixtureMessage>& messages);

}  // namespace cogmap::io::testing_util
