// `cogmap log-info` and `cogmap convert`: look into a log, and turn any log the
// readers know into the native text log (docs/log-format.md) or a RosAria-style
// ROS 1 bag (docs/inputs.md).
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <optional>

#include "app/command.h"
#include "app/log_warnings.h"
#include "app/progress.h"
#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/ev3_log.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/mrpt_rawlog.h"
#include "cogmap/io/ros1_bag.h"
#include "cogmap/sensors/as_sonar.h"
#include "cogmap/sensors/robot_json.h"

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

io::LogOpenOptions OpenOptions(const std::string& format, const std::vector<std::string>& topics,
                               const std::string& robot) {
  io::LogOpenOptions o;
  o.format = format;
  o.topics = topics;
  if (!robot.empty()) o.robot = sensors::ResolveRobot(robot);
  return o;
}

// The sensors, one line per run of sensors of one kind at one place
// ("  0-180  laser at (0, 0): -90 to 90 deg, step 1 deg, 0.02-8 m").
void PrintSensors(const sensors::RobotDescription& r) {
  const auto& s = r.sensors;
  for (size_t i = 0; i < s.size();) {
    size_t j = i + 1;
    if (s[i].kind == sensors::SensorKind::kLaser)
      while (j < s.size() && s[j].kind == s[i].kind && s[j].robot_from_sensor.x == s[i].robot_from_sensor.x &&
             s[j].robot_from_sensor.y == s[i].robot_from_sensor.y && s[j].max_range_m == s[i].max_range_m)
        ++j;
    const auto& a = s[i];
    const bool laser = a.kind == sensors::SensorKind::kLaser;
    if (j - i == 1) {
      std::printf("  %-9zu %s at (%.3f, %.3f) facing %.1f deg, cone %.1f deg, %.3g-%.3g m\n", i,
                  laser ? "laser beam" : "sonar", a.robot_from_sensor.x, a.robot_from_sensor.y,
                  RadToDeg(a.robot_from_sensor.theta), RadToDeg(a.beam_width_rad), a.min_range_m, a.max_range_m);
    } else {
      const std::string ids = std::to_string(i) + "-" + std::to_string(j - 1);
      std::printf("  %-9s laser of %zu beams at (%.3f, %.3f): %.2f to %.2f deg, %.3g-%.3g m\n", ids.c_str(), j - i,
                  a.robot_from_sensor.x, a.robot_from_sensor.y, RadToDeg(a.robot_from_sensor.theta),
                  RadToDeg(s[j - 1].robot_from_sensor.theta), a.min_range_m, a.max_range_m);
    }
    i = j;
  }
}

std::string RobotSummary(const sensors::RobotDescription& r) {
  char buf[256];
  double max_range = 0;
  for (const auto& s : r.sensors) max_range = std::max(max_range, s.max_range_m);
  std::snprintf(buf, sizeof buf, "%s (%zu sensors, max range %.4g m)", r.name.c_str(), r.sensors.size(), max_range);
  return buf;
}

int RunLogInfo(const std::string& path, const std::string& format, const std::vector<std::string>& topics,
               const std::string& robot_arg) {
  const std::string detected = format == "auto" ? io::DetectLogFormat(path) : format;
  auto reader = io::OpenLog(path, OpenOptions(detected, topics, robot_arg));
  const auto robot = reader->robot_hint();
  long records = 0, sweeps = 0, readings = 0, no_echo = 0, truths = 0, backwards = 0;
  double t_last = 0, t_min = std::numeric_limits<double>::infinity(), t_max = -t_min;
  double odom_m = 0, truth_m = 0;
  Pose2 last_odom;
  std::optional<Pose2> last_truth;
  ProgressBar bar("log-info");
  sensors::LogRecord r;
  while (reader->Next(&r)) {
    if (records > 0) {
      odom_m += std::hypot(r.odom.x - last_odom.x, r.odom.y - last_odom.y);
      if (r.time_s < t_last) ++backwards;
    }
    if (r.truth) {
      ++truths;
      if (last_truth) truth_m += std::hypot(r.truth->x - last_truth->x, r.truth->y - last_truth->y);
      last_truth = r.truth;
    }
    last_odom = r.odom;
    t_last = r.time_s;
    t_min = std::min(t_min, r.time_s);
    t_max = std::max(t_max, r.time_s);
    if (!r.ranges.empty()) ++sweeps;
    readings += static_cast<long>(r.ranges.size());
    if (robot)
      for (const auto& q : r.ranges)
        if (q.sensor >= 0 && q.sensor < static_cast<int>(robot->sensors.size()) &&
            q.range_m >= robot->sensors[q.sensor].max_range_m)
          ++no_echo;
    ++records;
    if (records % 1024 == 0) bar.Update(reader->progress());
  }
  bar.Finish();
  WarnSkipped(*reader);
  std::printf("log:            %s\n", path.c_str());
  std::printf("format:         %s\n", detected.c_str());
  std::printf("robot hint:     %s\n", robot ? RobotSummary(*robot).c_str() : "none (give --robot)");
  std::printf("records:        %ld (%ld with readings)\n", records, sweeps);
  std::printf("readings:       %ld (%ld at or beyond max range = no echo)\n", readings, no_echo);
  std::printf("time:           %.6g s to %.6g s, duration %.6g s%s\n", t_min, t_max, t_max - t_min,
              backwards ? (" (" + std::to_string(backwards) + " steps back in time)").c_str() : "");
  std::printf("odometry path:  %.3f m\n", odom_m);
  if (truths)
    std::printf("ground truth:   yes, %ld records, path %.3f m\n", truths, truth_m);
  else
    std::printf("ground truth:   no\n");
  const auto contents = reader->contents();
  if (!contents.empty()) {
    std::printf("contents:       %zu topics or message types\n", contents.size());
    size_t w = 0;
    for (const auto& c : contents) w = std::max(w, c.name.size());
    for (const auto& c : contents)
      std::printf("  %-*s %-26s %8ld  %s\n", static_cast<int>(w), c.name.c_str(), c.type.c_str(), c.count,
                  c.use.empty() ? "not used" : c.use.c_str());
  }
  if (robot) {
    std::printf("robot sensors:\n");
    PrintSensors(*robot);
  }
  if (const auto* ev3 = dynamic_cast<const io::Ev3LogReader*>(reader.get()))
    std::printf("ev3 samples:    %d per bearing; %ld lines where a bearing's samples spread over %.0f cm\n",
                ev3->samples_per_bearing(), ev3->disagreeing_lines(), io::kEv3DisagreeCm);
  return 0;
}

int RunConvert(const std::string& path, const std::string& format, const std::vector<std::string>& topics,
               const std::string& robot_arg, const std::string& as_sonar_arg, const std::string& to,
               const std::string& out_path) {
  auto reader = io::OpenLog(path, OpenOptions(format, topics, robot_arg));
  sensors::RobotDescription robot;
  if (!robot_arg.empty()) robot = sensors::ResolveRobot(robot_arg);
  else if (reader->robot_hint()) robot = *reader->robot_hint();
  else throw InputError(path, 0, "the log does not say which robot recorded it: give --robot NAME|FILE");
  const int n_sensors = static_cast<int>(robot.sensors.size());
  // --as-sonar: the log's readings become those of a sonar ring (the nearest
  // echo in each sonar's cone), written under the sonar robot's name.
  std::optional<sensors::RobotDescription> sonar;
  std::optional<sensors::AsSonar> as_sonar;
  if (!as_sonar_arg.empty()) {
    sonar = sensors::ResolveRobot(as_sonar_arg);
    as_sonar.emplace(robot, *sonar);
  }
  long records = 0, readings = 0;
  ProgressBar bar("convert");
  // The next record, checked against the robot and turned to sonar if asked.
  auto next = [&](sensors::LogRecord* r) {
    if (!reader->Next(r)) return false;
    for (const auto& q : r->ranges)
      if (q.sensor < 0 || q.sensor >= n_sensors)
        throw InputError(path, 0, "reading of sensor " + std::to_string(q.sensor) + " but robot '" + robot.name +
                                      "' has " + std::to_string(n_sensors) + " sensors");
    if (as_sonar) r->ranges = as_sonar->Convert(r->ranges);
    ++records;
    readings += static_cast<long>(r->ranges.size());
    if (records % 1024 == 0) bar.Update(reader->progress());
    return true;
  };
  if (to == "rosbag") {
    io::WriteRosAriaBag(out_path, sonar ? *sonar : robot, next);
  } else if (to == "rawlog") {
    io::WriteMrptRawlog(out_path, sonar ? *sonar : robot, next);
  } else {
    io::WriteFileAtomically(out_path, [&](std::ostream& out) {
      io::NativeLogWriter writer(out, sonar ? *sonar : robot);
      sensors::LogRecord r;
      while (next(&r)) writer.Write(r);
    });
  }
  bar.Finish();
  WarnSkipped(*reader);
  std::printf("wrote %s: %ld records, %ld readings, robot %s%s\n", out_path.c_str(), records, readings,
              sonar ? sonar->name.c_str() : robot.name.c_str(),
              sonar ? (" (sonar readings derived from " + robot.name + ")").c_str() : "");
  if (as_sonar) {
    int unseen = 0;
    for (bool c : as_sonar->covered()) unseen += c ? 0 : 1;
    if (unseen)
      std::printf("%d of %zu sonars point where %s does not look: they have no readings\n", unseen,
                  sonar->sensors.size(), robot.name.c_str());
  }
  return 0;
}

const bool kInfoRegistered = RegisterCommand(
    {"log-info", "Summarise a log: format, records, readings, duration, distance, robot", 10,
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       auto format = std::make_shared<std::string>("auto");
       auto topics = std::make_shared<std::vector<std::string>>();
       auto robot = std::make_shared<std::string>();
       sub.add_option("LOG", *path, "Log file (.gz accepted), the pioneer folder, or a bag")->required();
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       sub.add_option("--topics", *topics, kTopicsHelp)->delimiter(',');
       sub.add_option("--robot", *robot, kRobotHelp);
       return [=] { return RunLogInfo(*path, *format, *topics, *robot); };
     }});

const bool kConvertRegistered = RegisterCommand(
    {"convert", "Convert a log (CARMEN, pioneer, EV3, bags, rawlogs, native) into the native text log, a RosAria-style ROS 1 bag or an MRPT rawlog", 11,
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       auto format = std::make_shared<std::string>("auto");
       auto robot = std::make_shared<std::string>();
       auto out = std::make_shared<std::string>();
       auto as_sonar = std::make_shared<std::string>();
       auto topics = std::make_shared<std::vector<std::string>>();
       auto to = std::make_shared<std::string>("native");
       sub.add_option("LOG", *path, "Log file (.gz accepted), the pioneer folder, or a bag")->required();
       sub.add_option("OUT", *out, "Output file (or give -o)");
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       sub.add_option("--topics", *topics, kTopicsHelp)->delimiter(',');
       sub.add_option("--to", *to,
                      "Output format: native (the text log), or rosbag (a ROS 1 bag as RosAria records it: "
                      "/RosAria/pose Odometry, /tf, sonar as PointCloud on /RosAria/sonar, lasers as LaserScan on "
                      "/scan, /base_pose_ground_truth, sensor frames in /tf_static), or rawlog (an MRPT "
                      "observations-only rawlog: CObservationOdometry, CObservationRange, CObservation2DRangeScan); "
                      "docs/inputs.md")
           ->check(CLI::IsMember({"native", "rosbag", "rawlog"}))
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
       sub.add_option("-o,--output", *out, "File to write (written atomically)");
       return [=] {
         if (out->empty()) throw InputError("convert: give the file to write (OUT or -o)");
         return RunConvert(*path, *format, *topics, *robot, *as_sonar, *to, *out);
       };
     }});

}  // namespace
}  // namespace cogmap::app
