#pragma once
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::io {

// One topic or message type of a log, for `cogmap log-info`.
struct LogContent {
  std::string name;  // "/RosAria/sonar", or a type for formats without topics
  std::string type;  // "sensor_msgs/PointCloud"
  long count = 0;    // messages
  std::string use;   // "sonar ring of pioneer16 (sensors 0-15)", "odometry", "" = not used
};

// A run read one record at a time, so that long logs never sit in memory.
// Readers count lines: every InputError they throw names the file, the line
// and the problem ("run.log:112: expected 18 fields, got 17").
class LogReader {
 public:
  virtual ~LogReader() = default;
  // Reads the next record. Returns false at the end of the log. Throws
  // InputError on malformed input (including a truncated .gz).
  virtual bool Next(sensors::LogRecord* record) = 0;
  // The robot this log was recorded with, when the format says (a CARMEN laser
  // of n beams, the native log's "robot" header, the EV3's bearings).
  virtual std::optional<sensors::RobotDescription> robot_hint() const { return std::nullopt; }
  // Messages the reader skipped, by type, with their counts ("NEFF" -> 910):
  // complete once Next() has returned false (the CARMEN reader knows them from
  // opening). The library never prints: the app names each type once in a
  // warning ("cogmap: warning: LOG: skipped 910 NEFF messages").
  virtual std::map<std::string, long> skipped() const { return {}; }
  // Fraction of the input consumed so far, in [0, 1] (for progress bars).
  virtual double progress() const = 0;
  // The path as given by the user (for messages).
  virtual const std::string& path() const = 0;
  // What the log holds, for `cogmap log-info`: one entry per topic (bags) or
  // message type (rawlogs), with its count and what the reader made of it
  // (empty when unused). Formats that do not say return nothing.
  virtual std::vector<LogContent> contents() const { return {}; }
};

// Choices for formats that hold more than cogmap needs (ROS bags) or that
// carry readings without the sensors' poses (a RosAria sonar point cloud).
struct LogOpenOptions {
  std::string format = "auto";
  // Bags: the topics to read (range, odometry, tf); empty: found by type
  // (docs/inputs.md).
  std::vector<std::string> topics;
  // The robot the user named (--robot): the sensors of a sonar point cloud,
  // and sensor poses that tf does not give.
  std::optional<sensors::RobotDescription> robot;
};

// The built-in robot (sensors::BuiltinRobot) whose sensors equal 'robot's
// within 'tolerance' (poses in metres and radians, cones, ranges), if any: a
// log that stores geometry as float32 or quaternions reads back as the robot
// it was written from.
std::optional<sensors::RobotDescription> MatchingBuiltinRobot(const sensors::RobotDescription& robot,
                                                              double tolerance = 1e-6);

// A laser of the robot as a scanner: consecutive laser sensors at one place
// with one range interval, evenly spaced in angle (beam k at angle_min_rad +
// k * increment_rad). For writers of formats with scans (bags, rawlogs).
struct LaserFan {
  int first = 0, count = 0;
  double angle_min_rad = 0, increment_rad = 0;
};
std::vector<LaserFan> LaserFans(const sensors::RobotDescription& robot);

// Log formats: "native", "carmen", "pioneer" (measurement.txt + poses.txt:
// give either file or their folder), "ev3", "rosbag" (ROS 1 .bag), "ros2bag"
// (ROS 2 sqlite3 bag: its folder, metadata.yaml or a .db3), or "auto" (by
// content).
std::vector<std::string> LogFormatNames();

// Opens a log. Throws InputError naming the file for a missing file, an
// unknown format, or content that no reader recognises. "-" is standard input
// (any format but pioneer; gzip too): the format is told from its buffered
// head, which the reader then reads again (log_lines.h), so the stream is read
// once.
std::unique_ptr<LogReader> OpenLog(const std::string& path, const std::string& format = "auto");
std::unique_ptr<LogReader> OpenLog(const std::string& path, const LogOpenOptions& options);

// The options from what a user gives on a command line: a format name, bag
// topics, and a robot spec (a built-in name or robot JSON file; "" = none).
LogOpenOptions MakeOpenOptions(const std::string& format, const std::vector<std::string>& topics = {},
                               const std::string& robot_spec = "");

// The robot to map a log with: the one the user named (robot_spec: built-in
// name or robot JSON file), else the one the log says, else pioneer16.
sensors::RobotDescription RobotFor(const LogReader& log, const std::string& robot_spec);

// The format OpenLog(path, "auto") would choose ("native", "carmen", "pioneer",
// "ev3", "rosbag", "ros2bag"); InputError when the content matches none. For "-" it looks at the
// head of standard input only (calling it before OpenLog("-") is fine).
std::string DetectLogFormat(const std::string& path);

// What identifies a log from one run to the next (`cogmap map --resume`
// given the log the store was mapped from): "crc32 HEX BYTES", zlib's CRC-32
// of the file's first BYTES bytes (all of it up to 1 MiB), so that a log
// that has grown since (a recording still going on) is still that log; for a
// folder (a ROS 2 bag) "folder-crc32 HEX" over its files' names, sizes and
// first 64 KiB. Empty for standard input and a path that cannot be read (no
// identity: such a log is never taken to be the stored one).
std::string LogFingerprint(const std::string& path);
// Whether 'path' is the log 'fingerprint' was taken of (or that log grown).
bool IsLogOf(const std::string& path, const std::string& fingerprint);
// Whether 'text' is a fingerprint LogFingerprint could have made (empty
// included: standard input): a store's that is not was damaged.
bool IsFingerprint(const std::string& text);

}  // namespace cogmap::io
