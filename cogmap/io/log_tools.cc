#include "cogmap/io/log_tools.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <limits>
#include <optional>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/text.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/io/carmen_writer.h"
#include "cogmap/io/ev3_log.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/mrpt_rawlog.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/ros1_bag.h"
#include "cogmap/io/ros2_bag.h"
#include "cogmap/sensors/as_sonar.h"
#include "cogmap/sensors/robot_json.h"

namespace cogmap::io {
namespace {

std::string RobotSummary(const sensors::RobotDescription& r) {
  char buf[256];
  double max_range = 0;
  for (const auto& s : r.sensors) max_range = std::max(max_range, s.max_range_m);
  std::snprintf(buf, sizeof buf, "%s (%zu sensors, max range %.4g m)", r.name.c_str(), r.sensors.size(), max_range);
  return buf;
}

// The sensors, one line per run of sensors of one kind at one place
// ("  0-180  laser at (0, 0): -90 to 90 deg, step 1 deg, 0.02-8 m").
void DescribeSensors(const sensors::RobotDescription& r, std::string* out) {
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
      AppendF(out, "  %-9zu %s at (%.3f, %.3f) facing %.1f deg, cone %.1f deg, %.3g-%.3g m\n", i,
                  laser ? "laser beam" : "sonar", a.robot_from_sensor.x, a.robot_from_sensor.y,
                  RadToDeg(a.robot_from_sensor.theta), RadToDeg(a.beam_width_rad), a.min_range_m, a.max_range_m);
    } else {
      const std::string ids = std::to_string(i) + "-" + std::to_string(j - 1);
      AppendF(out, "  %-9s laser of %zu beams at (%.3f, %.3f): %.2f to %.2f deg, %.3g-%.3g m\n", ids.c_str(), j - i,
                  a.robot_from_sensor.x, a.robot_from_sensor.y, RadToDeg(a.robot_from_sensor.theta),
                  RadToDeg(s[j - 1].robot_from_sensor.theta), a.min_range_m, a.max_range_m);
    }
    i = j;
  }
}

}  // namespace

LogSummary SummarizeLog(const std::string& path, const LogToolOptions& o,
                        const std::function<void(double)>& progress) {
  const std::string detected = o.format == "auto" ? DetectLogFormat(path) : o.format;
  auto reader = OpenLog(path, MakeOpenOptions(detected, o.topics, o.robot));
  const auto robot = reader->robot_hint();
  long records = 0, sweeps = 0, readings = 0, no_echo = 0, truths = 0, backwards = 0;
  double t_last = 0, t_min = std::numeric_limits<double>::infinity(), t_max = -t_min;
  double odom_m = 0, truth_m = 0;
  Pose2 last_odom;
  std::optional<Pose2> last_truth;
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
    if (records % 1024 == 0 && progress) progress(reader->progress());
  }
  LogSummary s;
  s.skipped = reader->skipped();
  std::string* out = &s.text;
  AppendF(out, "log:            %s\n", path.c_str());
  AppendF(out, "format:         %s\n", detected.c_str());
  AppendF(out, "robot hint:     %s\n", robot ? RobotSummary(*robot).c_str() : "none (give --robot)");
  AppendF(out, "records:        %ld (%ld with readings)\n", records, sweeps);
  AppendF(out, "readings:       %ld (%ld at or beyond max range = no echo)\n", readings, no_echo);
  AppendF(out, "time:           %.6g s to %.6g s, duration %.6g s%s\n", t_min, t_max, t_max - t_min,
              backwards ? (" (" + std::to_string(backwards) + " steps back in time)").c_str() : "");
  AppendF(out, "odometry path:  %.3f m\n", odom_m);
  if (truths)
    AppendF(out, "ground truth:   yes, %ld records, path %.3f m\n", truths, truth_m);
  else
    AppendF(out, "ground truth:   no\n");
  const auto contents = reader->contents();
  if (!contents.empty()) {
    AppendF(out, "contents:       %zu topics or message types\n", contents.size());
    size_t w = 0;
    for (const auto& c : contents) w = std::max(w, c.name.size());
    for (const auto& c : contents)
      AppendF(out, "  %-*s %-26s %8ld  %s\n", static_cast<int>(w), c.name.c_str(), c.type.c_str(), c.count,
                  c.use.empty() ? "not used" : c.use.c_str());
  }
  if (robot) {
    AppendF(out, "robot sensors:\n");
    DescribeSensors(*robot, out);
  }
  if (const auto* ev3 = dynamic_cast<const Ev3LogReader*>(reader.get()))
    AppendF(out, "ev3 samples:    %d per bearing; %ld lines where a bearing's samples spread over %.0f cm\n",
                ev3->samples_per_bearing(), ev3->disagreeing_lines(), kEv3DisagreeCm);
  return s;
}

ConvertSummary ConvertLog(const std::string& path, const LogToolOptions& o, const std::string& to,
                          const std::string& out_path, const std::function<void(double)>& progress) {
  auto reader = OpenLog(path, MakeOpenOptions(o.format, o.topics, o.robot));
  sensors::RobotDescription robot;
  if (!o.robot.empty()) robot = sensors::ResolveRobot(o.robot);
  else if (reader->robot_hint()) robot = *reader->robot_hint();
  else throw InputError(path, 0, "the log does not say which robot recorded it: give --robot NAME|FILE");
  const int n_sensors = static_cast<int>(robot.sensors.size());
  // --as-sonar: the log's readings become those of a sonar ring (the nearest
  // echo in each sonar's cone), written under the sonar robot's name.
  std::optional<sensors::RobotDescription> sonar;
  std::optional<sensors::AsSonar> as_sonar;
  if (!o.as_sonar.empty()) {
    sonar = sensors::ResolveRobot(o.as_sonar);
    // A sonar ring read from a laser: any other pair is no conversion this
    // does (a laser's beams "read" from a laser were written as sonar readings).
    auto count = [](const sensors::RobotDescription& r, sensors::SensorKind kind) {
      return std::count_if(r.sensors.begin(), r.sensors.end(), [&](const auto& x) { return x.kind == kind; });
    };
    if (sonar->sensors.empty() || count(*sonar, sensors::SensorKind::kSonar) != static_cast<long>(sonar->sensors.size()))
      throw InputError("--as-sonar " + o.as_sonar + ": robot '" + sonar->name + "' is not a sonar ring (" +
                       std::to_string(count(*sonar, sensors::SensorKind::kLaser)) + " of its " +
                       std::to_string(sonar->sensors.size()) + " sensors are laser beams)");
    if (count(robot, sensors::SensorKind::kLaser) == 0)
      throw InputError(path + ": --as-sonar turns a laser's readings into sonar readings, and robot '" + robot.name +
                       "' has no laser");
    as_sonar.emplace(robot, *sonar);
  }
  long records = 0, readings = 0;
  // --as-sonar: how often the ring fires, per metre of odometry.
  long sweeps = 0;
  const bool ring_timing = as_sonar && o.ring_timing == "pioneer";
  if (as_sonar && !ring_timing && o.ring_timing != "scans")
    throw InputError("--ring-timing " + o.ring_timing + ": not a timing (pioneer, scans)");
  // The ring's timing (ring_timing): the target's sonars in banks of
  // kBankSize by index, each bank firing its next transducer every
  // kSonarInterval seconds of the log's clock (a Pioneer's, as cogmap
  // simulate fires it). A record fires the transducers whose turn came since
  // the record before, at most one sweep of each bank (a gap in the log is
  // no burst of readings at one pose).
  constexpr double kSonarInterval = 0.04;
  constexpr int kBankSize = 8;
  std::vector<std::vector<int>> banks;
  if (sonar)
    for (int k = 0; k < static_cast<int>(sonar->sensors.size()); ++k) {
      if (banks.empty() || static_cast<int>(banks.back().size()) >= kBankSize) banks.emplace_back();
      banks.back().push_back(k);
    }
  long slot = 0;
  std::optional<double> fired_until;
  // A clock that does not advance between records (belgioioso's stamps have
  // six significant digits: 1.01893e+09 s) times the ring by the motion
  // instead: the time the robot would take to drive and turn that far at a
  // Pioneer's pace (kPaceMps, kPaceRadPerS), carried over between records.
  constexpr double kPaceMps = 0.5, kPaceRadPerS = 100.0 * kPi / 180.0;
  std::optional<Pose2> fired_at;
  double owed_s = 0.0;
  long clockless = 0;
  auto due = [&](double t, const Pose2& odom) {
    std::vector<int> out;
    const long sweep = banks.empty() ? 0 : static_cast<long>(banks.front().size());
    long n = 0;
    if (std::isfinite(t) && fired_until && t > *fired_until) {
      n = static_cast<long>(std::floor((t - *fired_until) / kSonarInterval + 1e-9));
      *fired_until += n * kSonarInterval;
      owed_s = 0.0;
    } else {
      // The first record starts the clock. One stamped at or before the
      // last (intel holds a few stamped 0) says nothing of the time since.
      if (std::isfinite(t) && !fired_until) fired_until = t;
      if (fired_at) {
        const double moved = std::max((odom.translation() - fired_at->translation()).norm() / kPaceMps,
                                      std::abs(NormalizeAngle(odom.theta - fired_at->theta)) / kPaceRadPerS);
        clockless += moved > 0.0 ? 1 : 0;
        owed_s += moved;
        n = static_cast<long>(std::floor(owed_s / kSonarInterval + 1e-9));
        owed_s -= n * kSonarInterval;
      }
    }
    fired_at = odom;
    if (n > sweep) {
      n = sweep;
      if (std::isfinite(t)) fired_until = t;
      owed_s = 0.0;
    }
    for (long i = 0; i < n; ++i, ++slot)
      for (const auto& bank : banks) out.push_back(bank[slot % static_cast<long>(bank.size())]);
    return out;
  };
  // Records read but not yet written (ring_timing): those after the last
  // scan wait for the next, whose echoes their readings also take; at most
  // kMaxWaiting of them (the oldest then fire from the scans before alone).
  // Besides the scans either side, each reading takes the earlier scans of
  // the last metres driven, as far as the ring reaches (its longest max
  // range): a rear sonar reads the walls a forward laser saw on the way
  // in, where it looks. Those kept lie at least kHistoryStep apart along
  // the path (the cost of a reading stays bounded at any scan rate).
  constexpr double kHistoryStep = 0.25;
  double reach_m = 0.0;
  if (sonar)
    for (const auto& x : sonar->sensors) reach_m = std::max(reach_m, x.max_range_m);
  if (!std::isfinite(o.ring_history_m))
    throw InputError("--ring-history-m: not a distance (" + std::to_string(o.ring_history_m) + ")");
  if (o.ring_history_m >= 0.0) reach_m = o.ring_history_m;
  struct Past {
    sensors::SourceScan scan;
    double driven_m;
  };
  std::deque<Past> history;  // newest first
  double driven_m = 0.0;     // odometry path length of the records read
  std::optional<Pose2> read_odom;
  // (the records are written in the order read: over the whole log this is
  // also the path of those written)
  struct Waiting {
    sensors::LogRecord record;
    std::vector<int> fire;
  };
  constexpr size_t kMaxWaiting = 512;
  std::deque<Waiting> waiting;
  std::deque<sensors::LogRecord> ready;
  std::optional<sensors::SourceScan> last_scan;
  bool source_done = false;
  // The scans a reading takes: those given, and the history's.
  auto release = [&](Waiting w, std::vector<const sensors::SourceScan*> scans) {
    for (const Past& p : history) scans.push_back(&p.scan);
    w.record.ranges = as_sonar->FireAt(w.record.odom, w.fire, scans);
    ready.push_back(std::move(w.record));
  };
  // The last scan passes into the history when the next arrives, if it lies
  // a step beyond the history's newest; scans farther back than the ring
  // reaches leave it.
  auto remember = [&](sensors::SourceScan scan, double at_m) {
    if (!(reach_m > 0.0)) return;
    if (history.empty() || at_m - history.front().driven_m >= kHistoryStep)
      history.push_front({std::move(scan), at_m});
    while (!history.empty() && driven_m - history.back().driven_m > reach_m) history.pop_back();
  };
  double last_scan_m = 0.0;
  // The next source record, checked against the robot.
  auto read = [&](sensors::LogRecord* r) {
    if (!reader->Next(r)) return false;
    if (read_odom) driven_m += (r->odom.translation() - read_odom->translation()).norm();
    read_odom = r->odom;
    for (const auto& q : r->ranges)
      if (q.sensor < 0 || q.sensor >= n_sensors)
        throw InputError(path, 0, "reading of sensor " + std::to_string(q.sensor) + " but robot '" + robot.name +
                                      "' has " + std::to_string(n_sensors) + " sensors");
    return true;
  };
  // The next record to write, turned to sonar if asked.
  auto next = [&](sensors::LogRecord* r) {
    if (ring_timing) {
      while (ready.empty() && !source_done) {
        sensors::LogRecord in;
        if (!read(&in)) {
          source_done = true;
          while (!waiting.empty()) {
            release(std::move(waiting.front()), {&*last_scan});
            waiting.pop_front();
          }
          break;
        }
        Waiting w{std::move(in), {}};
        w.fire = due(w.record.time_s, w.record.odom);
        if (!w.record.ranges.empty()) {
          sensors::SourceScan scan = as_sonar->Echoes(w.record.odom, w.record.ranges);
          std::vector<const sensors::SourceScan*> both{&scan};
          if (last_scan) both.push_back(&*last_scan);
          while (!waiting.empty()) {
            release(std::move(waiting.front()), both);
            waiting.pop_front();
          }
          release(std::move(w), both);
          if (last_scan) remember(std::move(*last_scan), last_scan_m);
          last_scan = std::move(scan);
          last_scan_m = driven_m;
        } else if (!last_scan) {
          w.record.ranges.clear();
          ready.push_back(std::move(w.record));  // nothing seen yet
        } else {
          waiting.push_back(std::move(w));
          if (waiting.size() > kMaxWaiting) {
            release(std::move(waiting.front()), {&*last_scan});
            waiting.pop_front();
          }
        }
      }
      if (ready.empty()) return false;
      *r = std::move(ready.front());
      ready.pop_front();
    } else {
      if (!read(r)) return false;
      if (as_sonar) r->ranges = as_sonar->Convert(r->ranges);
    }
    if (as_sonar) sweeps += r->ranges.empty() ? 0 : 1;
    ++records;
    readings += static_cast<long>(r->ranges.size());
    if (records % 1024 == 0 && progress) progress(reader->progress());
    return true;
  };
  if (to == "rosbag") {
    WriteRosAriaBag(out_path, sonar ? *sonar : robot, next);
  } else if (to == "ros2bag") {
    WriteRosAriaBag2(out_path, sonar ? *sonar : robot, next);
  } else if (to == "rawlog") {
    WriteMrptRawlog(out_path, sonar ? *sonar : robot, next);
  } else if (to == "carmen") {
    WriteFileAtomically(out_path, [&](std::ostream& out) {
      CarmenLogWriter writer(out, sonar ? *sonar : robot, path);
      sensors::LogRecord r;
      while (next(&r)) writer.Write(r);
    });
  } else if (to == "native") {
    WriteFileAtomically(out_path, [&](std::ostream& out) {
      NativeLogWriter writer(out, sonar ? *sonar : robot);
      sensors::LogRecord r;
      while (next(&r)) writer.Write(r);
    });
  } else {
    throw InputError(out_path, 0, "unknown output format '" + to + "' (native, rosbag, ros2bag, rawlog, carmen)");
  }
  ConvertSummary s;
  s.skipped = reader->skipped();
  std::string* out = &s.text;
  AppendF(out, "wrote %s: %ld records, %ld readings, robot %s%s\n", out_path.c_str(), records, readings,
              sonar ? sonar->name.c_str() : robot.name.c_str(),
              sonar ? (" (sonar readings derived from " + robot.name + ")").c_str() : "");
  if (as_sonar) {
    int unseen = 0;
    for (bool c : as_sonar->covered()) unseen += c ? 0 : 1;
    if (unseen && !ring_timing)
      AppendF(out, "%d of %zu sonars point where %s does not look: they have no readings\n", unseen,
                  sonar->sensors.size(), robot.name.c_str());
    if (unseen && ring_timing && reach_m > 0.0)
      AppendF(out,
              "%d of %zu sonars point where %s does not look from the robot: they read only what its scans of "
              "the last %.0f m saw there\n",
              unseen, sonar->sensors.size(), robot.name.c_str(), reach_m);
    if (unseen && ring_timing && !(reach_m > 0.0))
      AppendF(out, "%d of %zu sonars point where %s does not look from the robot: they read only what the scans "
                   "either side saw there\n", unseen, sonar->sensors.size(), robot.name.c_str());
    // How often the ring fires, against the odometry's path (a Pioneer's
    // ring fires every few centimetres).
    if (!ring_timing && sweeps > 0 && driven_m > 0.0)
      AppendF(out, "the ring fires at %ld of %ld records (the laser's scans): once every %.2f m of the %.0f m driven\n",
              sweeps, records, driven_m / static_cast<double>(sweeps), driven_m);
    if (ring_timing && readings > 0 && driven_m > 0.0)
      AppendF(out,
              "the ring fires as a Pioneer's (one sonar per bank every %.0f ms): %ld readings in %ld of %ld records, "
              "one every %.3f m of the %.0f m driven; each from the laser scans before and after it\n",
              1000.0 * kSonarInterval, readings, sweeps, records, driven_m / static_cast<double>(readings), driven_m);
    if (ring_timing && clockless > 0)
      AppendF(out,
              "the log's clock did not advance over %ld of %ld records where the robot moved: the ring fired there by "
              "the distance and turn driven, at %.1f m/s and %.0f deg/s\n",
              clockless, records, kPaceMps, kPaceRadPerS * 180.0 / kPi);
    if (readings == 0)
      AppendF(out, "warning: no sonar readings were derived (no laser scan, or the log's clock never advances)\n");
  }
  return s;
}

}  // namespace cogmap::io
