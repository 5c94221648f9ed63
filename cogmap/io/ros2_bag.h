#pragma once
// ROS 2 bags in the sqlite3 storage (rosbag2's default before Iron): a folder
// with metadata.yaml and one or more .db3 files, each with the tables
//   topics(id, name, type, serialization_format, offered_qos_profiles, ...)
//   messages(id, topic_id, timestamp, data)
// read with SQLite; message data in CDR (cdr.h). Give the folder, its
// metadata.yaml, or a .db3 (alone, or with the metadata.yaml beside it). The
// .db3 files listed in metadata.yaml are read one after the other (a split
// bag's files follow each other in time). Another storage (MCAP: metadata.yaml
// says storage_identifier: mcap, or a .mcap file) or serialization is an
// InputError. What the reader makes of the messages is in ros_log.h.
#include <functional>
#include <memory>
#include <string>

#include "cogmap/io/log_reader.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

std::unique_ptr<LogReader> OpenRos2Bag(const std::string& path, const LogOpenOptions& options = {});

// Writes records as a ROS 2 sqlite3 bag folder 'path' (metadata.yaml and
// <name>_0.db3, rosbag2's schema, messages in CDR) with the topics and
// messages of WriteRosAriaBag (ros1_bag.h), the types in their ROS 2 names
// (nav_msgs/msg/Odometry, ...). The folder must not exist; it is written
// whole or not at all (a temporary folder renamed at the end). Topics carry no
// QoS profiles (rosbag2 then uses its defaults). Returns the number of records.
long WriteRosAriaBag2(const std::string& path, const sensors::RobotDescription& robot,
                      const std::function<bool(sensors::LogRecord*)>& next);

}  // namespace cogmap::io
