// `cogmap log-info` and `cogmap convert`: look into a log, and turn any log the
// readers know into the native text log (docs/log-format.md), a RosAria-style
// ROS 1 bag or an MRPT rawlog (docs/inputs.md). The work is io::SummarizeLog
// and io::ConvertLog.
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/command.h"
#include "app/log_warnings.h"
#include "app/progress.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/log_tools.h"

namespace cogmap::app {
namespace {

std::string FormatHelp() {
  std::string s = "Log format: ";
  for (const auto& f : io::LogFormatNames()) s += f + " ";
  return s + "(auto = by content; pioneer = measurement.txt + poses.txt, give either or their folder)";
}

const char* kTopicsHelp =
    "Bags: the topics to read, comma separated (range, odometry; tf is always read); default: found by type "
    "(docs/inputs.md)";
const char* kRobotHelp =
    "Robot: a built-in name (pioneer16, pioneer8, pioneer8-course, p2at16, laser) or a robot JSON file; for bags "
    "it also gives the sonars of a point cloud and sensor poses that tf does not give";


const bool kInfoRegistered = RegisterCommand(
    {"log-info", "Summarise a log: format, records, readings, duration, distance, robot", 10,
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       auto format = std::make_shared<std::string>("auto");
       auto topics = std::make_shared<std::vector<std::string>>();
       auto robot = std::make_shared<std::string>();
       sub.add_option("LOG", *path, "The log (any format cogmap reads: a file, .gz accepted, the pioneer folder, a bag or bag folder; - for standard input)")->required();
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       sub.add_option("--topics", *topics, kTopicsHelp)->delimiter(',');
       sub.add_option("--robot", *robot, kRobotHelp);
       return [=] {
         io::LogToolOptions o{*format, *topics, *robot, ""};
         ProgressBar bar("log-info");
         const io::LogSummary s = io::SummarizeLog(*path, o, [&bar](double f) { bar.Update(f); });
         bar.Finish();
         WarnSkipped(*path, s.skipped);
         std::fputs(s.text.c_str(), stdout);
         return 0;
       };
     }});

const bool kConvertRegistered = RegisterCommand(
    {"convert", "Convert a log (CARMEN, pioneer, EV3, bags, rawlogs, native) into the native text log, a RosAria-style ROS 1 or ROS 2 bag, an MRPT rawlog or a CARMEN log", 11,
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       auto format = std::make_shared<std::string>("auto");
       auto robot = std::make_shared<std::string>();
       auto out = std::make_shared<std::string>();
       auto as_sonar = std::make_shared<std::string>();
       auto ring_timing = std::make_shared<std::string>("pioneer");
       auto ring_history = std::make_shared<double>(-1.0);
       auto topics = std::make_shared<std::vector<std::string>>();
       auto to = std::make_shared<std::string>("native");
       sub.add_option("LOG", *path, "The log (any format cogmap reads: a file, .gz accepted, the pioneer folder, a bag or bag folder; - for standard input)")->required();
       sub.add_option("OUT", *out, "Output file (or give -o)");
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       sub.add_option("--topics", *topics, kTopicsHelp)->delimiter(',');
       sub.add_option("--to", *to,
                      "Output format: native (the text log), or rosbag (a ROS 1 bag as RosAria records it: "
                      "/RosAria/pose Odometry, /tf, sonar as PointCloud on /RosAria/sonar, lasers as LaserScan on "
                      "/scan, /base_pose_ground_truth, sensor frames in /tf_static), ros2bag (the same as a ROS 2 sqlite3 "
                      "bag folder, which must not exist), or rawlog (an MRPT "
                      "observations-only rawlog: CObservationOdometry, CObservationRange, CObservation2DRangeScan), or "
                      "carmen (ODOM or TRUEPOS, and SONAR for a sonar ring or ROBOTLASER1 for one laser; every "
                      "record with readings must hold all the sensors, as CARMEN's messages do); docs/inputs.md")
           ->check(CLI::IsMember({"native", "rosbag", "ros2bag", "rawlog", "carmen"}))
           ->capture_default_str();
       sub.add_option("--robot", *robot,
                      "Robot to write: a built-in name (pioneer16, pioneer8, pioneer8-course, p2at16, laser) or a "
                      "robot JSON file; default: the robot the log implies (for bags it also gives the sonars of a "
                      "point cloud and sensor poses that tf does not give)");
       sub.add_option("--as-sonar", *as_sonar,
                      "Turn a laser log into a sonar log: each sonar of this robot (built-in name or robot JSON file) "
                      "reads the nearest laser return inside its beam cone, or max range (no echo) when none; "
                      "sonars pointing where the laser does not look get no readings; odometry and reference "
                      "poses are kept");
       sub.add_option("--ring-timing", *ring_timing,
                      "With --as-sonar, when the ring fires: pioneer (as a Pioneer's and cogmap simulate's: one "
                      "sonar per bank of 8 every 40 ms by the log's clock, each reading taken from the laser scans "
                      "before and after it, moved by the odometry; a sonar reads nothing where neither scan looked) "
                      "or scans (the whole ring at each laser scan only)")
           ->check(CLI::IsMember({"pioneer", "scans"}))
           ->capture_default_str();
       sub.add_option("--ring-history-m", *ring_history,
                      "With --ring-timing pioneer, how far back along the path (metres) the earlier laser scans a "
                      "reading also takes reach, kept at least 0.25 m apart: a rear sonar reads the walls the laser "
                      "saw on the way in; default: the ring's longest max range; 0: the scans either side only")
           ->check(CLI::NonNegativeNumber);
       sub.add_option("-o,--output", *out, "File to write (written atomically)");
       return [=] {
         if (out->empty()) throw InputError("convert: give the file to write (OUT or -o)");
         io::LogToolOptions o{*format, *topics, *robot, *as_sonar, *ring_timing, *ring_history};
         ProgressBar bar("convert");
         const io::ConvertSummary s = io::ConvertLog(*path, o, *to, *out, [&bar](double f) { bar.Update(f); });
         bar.Finish();
         WarnSkipped(*path, s.skipped);
         std::fputs(s.text.c_str(), stdout);
         return 0;
       };
     }});

}  // namespace
}  // namespace cogmap::app
