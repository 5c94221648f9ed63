#pragma once
// What the ROS 1 and ROS 2 bag readers share: the reader that turns a bag's
// decoded messages (ros_messages.h) into LogRecords (docs/inputs.md):
//  - topics found by type, or chosen (LogOpenOptions::topics);
//  - the robot from the range topics' first messages, their frames placed by
//    tf_static (else /tf, else the robot description);
//  - odometry from nav_msgs/Odometry (or from the odom -> base transform in
//    /tf when the bag has no Odometry topic), interpolated at each reading's
//    stamp; a ground-truth Odometry topic ("...ground_truth...") gives truth;
//  - records in stamp order: one per odometry message, the readings of a scan
//    stamped like an odometry message joined to its record.
#include <functional>
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"
#include "cogmap/io/ros_messages.h"

namespace cogmap::io::ros {

// The reader over a bag. Reads the bag's tf_static, the start of /tf and the
// first message of each range topic at opening (InputError for a bag without
// range data or odometry, a topic cogmap cannot read, frames that tf does not
// connect).
std::unique_ptr<LogReader> OpenBagLog(std::unique_ptr<BagSource> source, const LogOpenOptions& options);

// The messages of a RosAria-style bag (ros1_bag.h, WriteRosAriaBag) of the
// records 'next' gives, written through 'bag' (not closed here); 'path' names
// the bag in errors. Returns the number of records.
long WriteRosAriaMessages(const std::string& path, const sensors::RobotDescription& robot,
                          const std::function<bool(sensors::LogRecord*)>& next, BagWriter& bag);

// Orders topic names with their numbers compared as numbers
// ("/sonar_2" < "/sonar_10").
bool NaturalLess(const std::string& a, const std::string& b);

}  // namespace cogmap::io::ros
