#pragma once
// ROS 1 bags (.bag, format 2.0), read and written through Debian's
// rosbag_storage (rosbag::Bag / rosbag::View) and the ROS 1 message headers.
// What the reader makes of a bag is in ros_log.h and docs/inputs.md.
#include <functional>
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

// The first bytes of every ROS 1 bag.
inline constexpr const char* kRos1BagMagic = "#ROSBAG V2.0";

// Opens a ROS 1 bag. Throws InputError naming the file for a bag rosbag
// cannot open (truncated: the index at its end is missing), and the file,
// topic and message for content that cannot be used (ros_log.h).
std::unique_ptr<LogReader> OpenRos1Bag(const std::string& path, const LogOpenOptions& options = {});

// Writes records as a bag like one recorded from RosAria on a Pioneer:
//   /RosAria/pose            nav_msgs/Odometry      odom -> base_link, one per record
//   /tf                      tf2_msgs/TFMessage     the same odom -> base_link
//   /RosAria/sonar           sensor_msgs/PointCloud the record's sonar readings as points in
//                                                   frame "sonar" (= base_link): transducer
//                                                   position + range along its axis
//   /scan (/scan_2, ...)     sensor_msgs/LaserScan  one per laser fan of the robot (consecutive
//                                                   laser sensors at one position, evenly spaced)
//   /base_pose_ground_truth  nav_msgs/Odometry      the true pose, when a record has one
//   /tf_static               tf2_msgs/TFMessage     base_link -> sonar, sonar_0..n-1 (each
//                                                   transducer), laser (laser_2, ...)
// Stamps are the records' times (ns); bag times too (at least 1 ns: rosbag
// refuses 0). 'next' gives the records until it returns false. Written all or
// nothing (a temporary file renamed at the end); InputError for a reading of a
// sensor the robot lacks, laser sensors that are no even fan, or a negative
// time. Returns the number of records written.
long WriteRosAriaBag(const std::string& path, const sensors::RobotDescription& robot,
                     const std::function<bool(sensors::LogRecord*)>& next);

}  // namespace cogmap::io
