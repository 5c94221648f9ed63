#pragma once
// What `cogmap log-info` and `cogmap convert` do, as library calls: a log
// summarised (format, records, readings, time, distance, topics or message
// types and their use, the robot's sensors), and a log converted into the
// native text log, a RosAria-style ROS 1 or ROS 2 bag, an MRPT rawlog or a
// CARMEN log.
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace cogmap::io {

struct LogToolOptions {
  std::string format = "auto";       // a LogFormatNames() entry
  std::vector<std::string> topics;   // bags: the topics to read ("" = by type)
  std::string robot;                 // a built-in robot or robot JSON ("" = the log's)
  std::string as_sonar;              // convert: a sonar robot whose readings the laser's become
  // convert --as-sonar: when the ring fires. "pioneer": as a Pioneer's does
  // (and cogmap simulate's), one transducer per bank of 8 every 40 ms by the
  // log's clock, each reading made from the laser scans before and after it
  // moved by the odometry; "scans": the whole ring at each laser scan.
  std::string ring_timing = "pioneer";
  // ... and how far back along the path the earlier scans a reading takes
  // reach (metres; negative: the ring's longest max range; 0: the scans
  // either side only).
  double ring_history_m = -1.0;
};

struct LogSummary {
  std::string text;                       // the report, one fact per line
  std::map<std::string, long> skipped;    // message types the reader skipped
};
struct ConvertSummary {
  std::string text;                       // what was written
  std::map<std::string, long> skipped;
};

// Reads the whole log. 'progress' gets the fraction read now and then.
LogSummary SummarizeLog(const std::string& path, const LogToolOptions& options,
                        const std::function<void(double)>& progress = {});
// Writes 'out_path' atomically: 'to' is "native", "rosbag", "ros2bag" (a
// folder), "rawlog" or "carmen" (carmen_writer.h).
ConvertSummary ConvertLog(const std::string& path, const LogToolOptions& options, const std::string& to,
                          const std::string& out_path, const std::function<void(double)>& progress = {});

}  // namespace cogmap::io
