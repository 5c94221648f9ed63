// `cogmap log-info` and `cogmap convert`: look into a log, and turn any log the
// readers know into the native text log (docs/log-format.md).
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
#include "cogmap/sensors/as_sonar.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::app {
namespace {

std::string FormatHelp() {
  std::string s = "Log format: ";
  for (const auto& f : io::LogFormatNames()) s += f + " ";
  return s + "(auto = by content; pioneer = measurement.txt + poses.txt, give either or their folder)";
}

std::string RobotSummary(const sensors::RobotDescription& r) {
  char buf[256];
  double max_range = 0;
  for (const auto& s : r.sensors) max_range = std::max(max_range, s.max_range_m);
  std::snprintf(buf, sizeof buf, "%s (%zu sensors, max range %.4g m)", r.name.c_str(), r.sensors.size(), max_range);
  return buf;
}

int RunLogInfo(const std::string& path, const std::string& format) {
  const std::string detected = format == "auto" ? io::DetectLogFormat(path) : format;
  auto reader = io::OpenLog(path, detected);
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
  if (const auto* ev3 = dynamic_cast<const io::Ev3LogReader*>(reader.get()))
    std::printf("ev3 samples:    %d per bearing; %ld lines where a bearing's samples spread over %.0f cm\n",
                ev3->samples_per_bearing(), ev3->disagreeing_lines(), io::kEv3DisagreeCm);
  return 0;
}

int RunConvert(const std::string& path, const std::string& format, const std::string& robot_arg,
               const std::string& as_sonar_arg, const std::string& out_path) {
  auto reader = io::OpenLog(path, format);
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
  io::WriteFileAtomically(out_path, [&](std::ostream& out) {
    io::NativeLogWriter writer(out, sonar ? *sonar : robot);
    sensors::LogRecord r;
    while (reader->Next(&r)) {
      for (const auto& q : r.ranges)
        if (q.sensor < 0 || q.sensor >= n_sensors)
          throw InputError(path, 0, "reading of sensor " + std::to_string(q.sensor) + " but robot '" + robot.name +
                                        "' has " + std::to_string(n_sensors) + " sensors");
      if (as_sonar) r.ranges = as_sonar->Convert(r.ranges);
      writer.Write(r);
      ++records;
      readings += static_cast<long>(r.ranges.size());
      if (records % 1024 == 0) bar.Update(reader->progress());
    }
  });
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
       sub.add_option("LOG", *path, "Log file (.gz accepted), or the pioneer folder")->required();
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       return [=] { return RunLogInfo(*path, *format); };
     }});

const bool kConvertRegistered = RegisterCommand(
    {"convert", "Convert a log (CARMEN, pioneer, EV3, native) into the native text log", 11,
     [](CLI::App& sub) -> std::function<int()> {
       auto path = std::make_shared<std::string>();
       auto format = std::make_shared<std::string>("auto");
       auto robot = std::make_shared<std::string>();
       auto out = std::make_shared<std::string>();
       auto as_sonar = std::make_shared<std::string>();
       sub.add_option("LOG", *path, "Log file (.gz accepted), or the pioneer folder")->required();
       sub.add_option("--format", *format, FormatHelp())->check(CLI::IsMember(io::LogFormatNames()));
       sub.add_option("--robot", *robot,
                      "Robot to write in the header: a built-in name (pioneer16, pioneer8, pioneer8-course, p2at16, laser) or a "
                      "robot JSON file; default: the robot the log implies");
       sub.add_option("--as-sonar", *as_sonar,
                      "Turn a laser log into a sonar log: each sonar of this robot (built-in name or robot JSON file) "
                      "reads the nearest laser return inside its beam cone, or max range (no echo) when none; "
                      "sonars pointing where the laser does not look get no readings; odometry and reference "
                      "poses are kept");
       sub.add_option("-o,--output", *out, "Native log to write (written atomically)")->required();
       return [=] { return RunConvert(*path, *format, *robot, *as_sonar, *out); };
     }});

}  // namespace
}  // namespace cogmap::app
