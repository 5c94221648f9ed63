#pragma once
// ROS 1 messages (the roscpp message classes) turned into the neutral structs
// of ros_messages.h: one conversion per type, shared by the ROS 1 bag reader
// (ros1_bag_source.cc) and the live node (ros/cogmap_node.cc). C++17, like
// the ROS 1 message headers it includes; no cogmap header that needs C++20.
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/Header.h>
#include <tf2_msgs/TFMessage.h>

#include <string>
#include <vector>

#include "cogmap/io/ros_messages.h"

namespace cogmap::io::ros {

inline int64_t Ros1Ns(const ::ros::Time& t) { return static_cast<int64_t>(t.sec) * 1000000000 + t.nsec; }
inline Header FromRos1(const std_msgs::Header& h) { return {Ros1Ns(h.stamp), h.frame_id}; }
inline Transform3 FromRos1(const geometry_msgs::Transform& t) {
  return {t.translation.x, t.translation.y, t.translation.z, t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w};
}
inline Transform3 FromRos1(const geometry_msgs::Pose& p) {
  return {p.position.x, p.position.y, p.position.z, p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w};
}

inline LaserScan FromRos1(const sensor_msgs::LaserScan& p) {
  LaserScan s;
  s.header = FromRos1(p.header);
  s.angle_min_rad = p.angle_min;
  s.angle_increment_rad = p.angle_increment;
  s.range_min_m = p.range_min;
  s.range_max_m = p.range_max;
  s.ranges = p.ranges;
  return s;
}

inline Range FromRos1(const sensor_msgs::Range& p) {
  Range r;
  r.header = FromRos1(p.header);
  r.radiation_type = p.radiation_type;
  r.field_of_view_rad = p.field_of_view;
  r.min_range_m = p.min_range;
  r.max_range_m = p.max_range;
  r.range_m = p.range;
  return r;
}

inline PointCloud FromRos1(const sensor_msgs::PointCloud& p) {
  PointCloud c;
  c.header = FromRos1(p.header);
  c.points.reserve(p.points.size());
  for (const auto& q : p.points) c.points.push_back({q.x, q.y, q.z});
  return c;
}

// The x, y, z of a PointCloud2; '*error' says why a cloud cannot be read ("" when fine).
inline PointCloud FromRos1(const sensor_msgs::PointCloud2& p, std::string* error) {
  PointCloud c;
  c.header = FromRos1(p.header);
  std::vector<PointField> fields;
  for (const auto& f : p.fields) fields.push_back({f.name, f.offset, f.datatype, f.count});
  *error = DecodePointCloud2(fields, p.is_bigendian, p.point_step, p.width, p.height, p.data.data(), p.data.size(),
                             &c.points);
  return c;
}

inline Odometry FromRos1(const nav_msgs::Odometry& p) {
  Odometry o;
  o.header = FromRos1(p.header);
  o.child_frame_id = p.child_frame_id;
  o.pose = FromRos1(p.pose.pose);
  return o;
}

inline TfMessage FromRos1(const tf2_msgs::TFMessage& p) {
  TfMessage tf;
  for (const auto& t : p.transforms) tf.transforms.push_back({FromRos1(t.header), t.child_frame_id, FromRos1(t.transform)});
  return tf;
}

}  // namespace cogmap::io::ros
