// Compiled as C++17 (ROS 1 message headers).
#include "cogmap/io/ros1_bag_test_fixture.h"

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <cstring>

namespace cogmap::io::testing_util {

void WriteFixtureBag(const std::string& path, const std::vector<FixtureMessage>& messages) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (const auto& m : messages) {
    const ::ros::Time t(static_cast<uint32_t>(m.time_ns / 1000000000), static_cast<uint32_t>(m.time_ns % 1000000000));
    std_msgs::Header h;
    h.stamp = t;
    h.frame_id = m.frame;
    switch (m.kind) {
      case FixtureMessage::kOdometry: {
        nav_msgs::Odometry o;
        o.header = h;
        o.child_frame_id = m.child;
        o.pose.pose.position.x = m.x;
        o.pose.pose.position.y = m.y;
        o.pose.pose.orientation.z = std::sin(m.yaw / 2);
        o.pose.pose.orientation.w = std::cos(m.yaw / 2);
        bag.write(m.topic, t, o);
        break;
      }
      case FixtureMessage::kLaserScan: {
        sensor_msgs::LaserScan s;
        s.header = h;
        s.angle_min = static_cast<float>(m.angle_min);
        s.angle_increment = static_cast<float>(m.angle_increment);
        s.angle_max = static_cast<float>(m.angle_min + (m.values.size() - 1) * m.angle_increment);
        s.range_min = static_cast<float>(m.range_min);
        s.range_max = static_cast<float>(m.range_max);
        s.ranges = m.values;
        bag.write(m.topic, t, s);
        break;
      }
      case FixtureMessage::kRange: {
        sensor_msgs::Range r;
        r.header = h;
        r.radiation_type = sensor_msgs::Range::ULTRASOUND;
        r.field_of_view = static_cast<float>(m.field_of_view);
        r.min_range = static_cast<float>(m.range_min);
        r.max_range = static_cast<float>(m.range_max);
        r.range = m.values.at(0);
        bag.write(m.topic, t, r);
        break;
      }
      case FixtureMessage::kPointCloud2: {
        sensor_msgs::PointCloud2 c;
        c.header = h;
        c.height = 1;
        c.width = static_cast<uint32_t>(m.values.size() / 3);
        for (int k = 0; k < 3; ++k) {
          sensor_msgs::PointField f;
          f.name = std::string(1, static_cast<char>('x' + k));
          f.offset = 4 * k;
          f.datatype = sensor_msgs::PointField::FLOAT32;
          f.count = 1;
          c.fields.push_back(f);
        }
        c.point_step = 12;
        c.row_step = 12 * c.width;
        c.is_bigendian = false;
        c.data.resize(m.values.size() * 4);
        std::memcpy(c.data.data(), m.values.data(), c.data.size());
        bag.write(m.topic, t, c);
        break;
      }
      case FixtureMessage::kTf: {
        tf2_msgs::TFMessage tf;
        geometry_msgs::TransformStamped s;
        s.header = h;
        s.child_frame_id = m.child;
        s.transform.translation.x = m.x;
        s.transform.translation.y = m.y;
        s.transform.rotation.z = std::sin(m.yaw / 2);
        s.transform.rotation.w = std::cos(m.yaw / 2);
        tf.transforms.push_back(s);
        bag.write(m.topic, t, tf);
        break;
      }
      case FixtureMessage::kString: {
        std_msgs::String s;
        s.data = "hello";
        bag.write(m.topic, t, s);
        break;
      }
    }
  }
  bag.close();
}

}  // namespace cogmap::io::testing_util
