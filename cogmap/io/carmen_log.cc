#include "cogmap/io/carmen_log.h"

#include <cmath>
#include <set>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"

namespace cogmap::io {
namespace {

constexpr double kSickNoReturnM = 81.9;       // SICK LMS reports 8191 cm for no return
constexpr double kMinNoReturnCodeM = 20.0;    // a largest reading at least this far is the code
constexpr double kMissingTimeS = 1e-9;        // smaller timestamps are "no timestamp"

struct Laser {
  bool present = false;
  int beams = 0;
  double max_seen_m = 0.0;
  double param_max_m = 0.0;
  double offset_m = 0.0;    // PARAM robot_{front,rear}laser_offset
  int first_sensor = 0;
  // ROBOTLASER1 only: geometry from the first message.
  double start_rad = 0.0, res_rad = 0.0, max_range_m = 0.0;
  Pose2 robot_from_laser;
};

double MaxRange(const Laser& l) {
  if (l.param_max_m > 0) return l.param_max_m;
  if (l.max_seen_m >= kMinNoReturnCodeM) return l.max_seen_m;
  return kSickNoReturnM;
}

class CarmenReader : public LogReader {
 public:
  explicit CarmenReader(const std::string& path) : src_(path) {
    PreScan(path);
    int next = 0;
    for (Laser* l : {&front_, &rear_, &robot_laser_}) {
      l->first_sensor = next;
      if (l->present) next += l->beams;
    }
    BuildRobot();
  }

  bool Next(sensors::LogRecord* out) override {
    std::string line;
    while (src_.Next(&line)) {
      const auto f = SplitFields(line);
      if (f.empty() || f[0][0] == '#') continue;
      if (f[0] == "ODOM") {
        Expect(f, 10, "ODOM x y theta tv rv accel timestamp host logger_timestamp");
        *out = {};
        out->odom = Pose(f, 1, "");
        out->time_s = Time(f, 7, 9);
        return true;
      }
      if (f[0] == "TRUEPOS") {
        Expect(f, 10, "TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp");
        *out = {};
        out->truth = Pose(f, 1, "true_");
        out->odom = Pose(f, 4, "odom_");
        out->time_s = Time(f, 7, 9);
        return true;
      }
      if (f[0] == "FLASER" || f[0] == "RLASER") {
        ReadOldLaser(f, f[0] == "FLASER" ? front_ : rear_, out);
        return true;
      }
      if (f[0] == "ROBOTLASER1") {
        ReadRobotLaser(f, out);
        return true;
      }
      if (f[0] == "PARAM") {
        if (f.size() < 3) Fail("PARAM: expected 'PARAM name value'");
      }
      // Any other message: skipped.
    }
    if (readings_ == 0) ThrowEmptyLog(src_.path());
    return false;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  double progress() const override { return src_.progress(); }
  const std::string& path() const override { return src_.path(); }

 private:
  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(src_.path(), src_.line_number(), problem);
  }
  void Expect(const std::vector<std::string_view>& f, size_t n, const std::string& form) const {
    if (f.size() != n)
      Fail(std::string(f[0]) + ": expected " + std::to_string(n) + " fields (" + form + "), got " +
           std::to_string(f.size()));
  }
  double Num(std::string_view t, const std::string& what) const {
    return ParseNumber(t, src_.path(), src_.line_number(), what);
  }
  Pose2 Pose(const std::vector<std::string_view>& f, size_t i, const std::string& prefix) const {
    return {Num(f[i], prefix + "x"), Num(f[i + 1], prefix + "y"), Num(f[i + 2], prefix + "theta")};
  }
  double Time(const std::vector<std::string_view>& f, size_t ipc, size_t logger) {
    // The Radish logs write 0 or uninitialised memory (1e-153, 6e-43...) as
    // the timestamp of the ODOM copied after each FLASER: treat as missing.
    auto missing = [](double v) { return std::abs(v) < kMissingTimeS; };
    double t = Num(f[ipc], "timestamp");
    if (missing(t)) t = Num(f[logger], "logger_timestamp");
    if (missing(t)) t = last_time_;
    last_time_ = t;
    return t;
  }
  void ReadRanges(const std::vector<std::string_view>& f, size_t first, int n, int sensor0,
                  sensors::LogRecord* out) {
    out->ranges.resize(n);
    for (int i = 0; i < n; ++i) {
      const double r = Num(f[first + i], "range");
      CheckRange(r, src_.path(), src_.line_number(), "beam " + std::to_string(i));
      out->ranges[i] = {sensor0 + i, r};
    }
    readings_ += n;
  }

  void ReadOldLaser(const std::vector<std::string_view>& f, const Laser& l, sensors::LogRecord* out) {
    if (f.size() < 2) Fail(std::string(f[0]) + ": missing the beam count");
    const long n = ParseCount(f[1], src_.path(), src_.line_number(), "beam count");
    if (n > 100000) Fail("beam count " + std::to_string(n) + " is absurd");
    Expect(f, 11 + n,
           "n r1..rn x y theta odom_x odom_y odom_theta timestamp host logger_timestamp with n = " +
               std::to_string(n));
    if (n != l.beams)
      Fail(std::string(f[0]) + " with " + std::to_string(n) + " beams, but the first one had " +
           std::to_string(l.beams));
    *out = {};
    ReadRanges(f, 2, static_cast<int>(n), l.first_sensor, out);
    out->truth = Pose(f, 2 + n, "");
    out->odom = Pose(f, 5 + n, "odom_");
    out->time_s = Time(f, 8 + n, 10 + n);
  }

  void ReadRobotLaser(const std::vector<std::string_view>& f, sensors::LogRecord* out) {
    if (f.size() < 10) Fail("ROBOTLASER1: too few fields");
    const long n = ParseCount(f[8], src_.path(), src_.line_number(), "beam count");
    if (n > 100000 || f.size() < 10 + static_cast<size_t>(n)) Fail("ROBOTLASER1: too few fields for the beams");
    const long m = ParseCount(f[9 + n], src_.path(), src_.line_number(), "remission count");
    Expect(f, 24 + n + m, "ROBOTLASER1 with " + std::to_string(n) + " beams and " + std::to_string(m) +
                              " remissions");
    if (n != robot_laser_.beams)
      Fail("ROBOTLASER1 with " + std::to_string(n) + " beams, but the first one had " +
           std::to_string(robot_laser_.beams));
    *out = {};
    ReadRanges(f, 9, static_cast<int>(n), robot_laser_.first_sensor, out);
    const size_t k = 10 + n + m;
    Pose(f, k, "laser_");
    out->odom = Pose(f, k + 3, "robot_");
    out->time_s = Time(f, k + 11, k + 13);
  }

  // One streaming pass at opening: PARAMs, which lasers, their beam counts and
  // largest readings. Lines it cannot parse are left for Next() to report.
  void PreScan(const std::string& path) {
    LineSource scan(path);
    std::string line;
    while (scan.Next(&line)) {
      const auto f = SplitFields(line);
      if (f.empty()) continue;
      try {
        if (f[0] == "PARAM" && f.size() >= 3) {
          const std::string name(f[1]);
          auto num = [&] { return ParseNumber(f[2], path, 0, name); };
          if (name == "robot_front_laser_max" || name == "laser_front_laser_max_range") front_.param_max_m = num();
          if (name == "robot_rear_laser_max" || name == "laser_rear_laser_max_range") rear_.param_max_m = num();
          if (name == "robot_frontlaser_offset") front_.offset_m = num();
          if (name == "robot_rearlaser_offset") rear_.offset_m = num();
        } else if ((f[0] == "FLASER" || f[0] == "RLASER") && f.size() >= 2) {
          Laser& l = f[0] == "FLASER" ? front_ : rear_;
          const long n = ParseCount(f[1], path, 0, "n");
          if (!l.present) {
            l.present = true;
            l.beams = static_cast<int>(n);
          }
          for (long i = 0; i < n && 2 + static_cast<size_t>(i) < f.size(); ++i)
            l.max_seen_m = std::max(l.max_seen_m, ParseNumber(f[2 + i], path, 0, "r"));
        } else if (f[0] == "ROBOTLASER1" && f.size() >= 10 && !robot_laser_.present) {
          const long n = ParseCount(f[8], path, 0, "n");
          if (f.size() < 10 + static_cast<size_t>(n)) continue;
          const long m = ParseCount(f[9 + n], path, 0, "m");
          if (f.size() != 24 + static_cast<size_t>(n + m)) continue;
          Laser& l = robot_laser_;
          l.start_rad = ParseNumber(f[2], path, 0, "start");
          l.res_rad = ParseNumber(f[4], path, 0, "res");
          l.max_range_m = ParseNumber(f[5], path, 0, "max");
          const size_t k = 10 + n + m;
          const Pose2 laser{ParseNumber(f[k], path, 0, "x"), ParseNumber(f[k + 1], path, 0, "y"),
                            ParseNumber(f[k + 2], path, 0, "t")};
          const Pose2 robot{ParseNumber(f[k + 3], path, 0, "x"), ParseNumber(f[k + 4], path, 0, "y"),
                            ParseNumber(f[k + 5], path, 0, "t")};
          l.robot_from_laser = robot.inverse() * laser;
          l.beams = static_cast<int>(n);
          l.present = true;
        }
      } catch (const InputError&) {
        // Reported with its line number when Next() reaches it.
      }
    }
  }

  void BuildRobot() {
    robot_.name = "carmen-laser";
    for (const Laser* l : {&front_, &rear_}) {
      if (!l->present || l->beams < 1) continue;
      sensors::LaserOptions o;
      o.beams = l->beams;
      o.fov_rad = CarmenLaserFov(l->beams);
      o.max_range_m = MaxRange(*l);
      o.min_range_m = 0.0;
      auto laser = sensors::MakeLaser(o);
      for (auto& s : laser.sensors) {
        if (l == &rear_) {
          s.robot_from_sensor.theta = NormalizeAngle(s.robot_from_sensor.theta + kPi);
          s.robot_from_sensor.x = -l->offset_m;
        } else {
          s.robot_from_sensor.x = l->offset_m;
        }
        robot_.sensors.push_back(s);
      }
    }
    if (robot_laser_.present && robot_laser_.beams >= 1) {
      const Laser& l = robot_laser_;
      for (int i = 0; i < l.beams; ++i) {
        sensors::RangeSensor s;
        s.robot_from_sensor = l.robot_from_laser * Pose2{0, 0, l.start_rad + i * l.res_rad};
        s.beam_width_rad = l.res_rad > 0 ? l.res_rad : DegToRad(1.0);
        s.min_range_m = 0.0;
        s.max_range_m = l.max_range_m > 0 ? l.max_range_m : MaxRange(l);
        s.kind = sensors::SensorKind::kLaser;
        robot_.sensors.push_back(s);
      }
    }
  }

  LineSource src_;
  Laser front_, rear_, robot_laser_;
  sensors::RobotDescription robot_;
  double last_time_ = 0.0;
  long readings_ = 0;
};

}  // namespace

double CarmenLaserFov(int beams) {
  switch (beams) {
    case 180: return DegToRad(179.0);
    case 181: return kPi;
    case 360: return DegToRad(179.5);
    case 361: return kPi;
    case 400: return DegToRad(99.75);
    case 401: return DegToRad(100.0);
    default: return kPi;
  }
}

bool IsCarmenMessageName(const std::string& w) {
  static const std::set<std::string> kNames = {
      "PARAM", "SYNC", "ODOM", "FLASER", "RLASER", "LASER1", "LASER2", "LASER3", "LASER4",
      "RAWLASER1", "RAWLASER2", "RAWLASER3", "RAWLASER4", "ROBOTLASER1", "ROBOTLASER2",
      "TRUEPOS", "NEFF", "GPSNMEA", "GPSGGA", "GPSRMC", "SONAR", "BUMPER", "SCANMARK",
      "POSITIONLASER", "IMU", "VECTORMOVE", "ROBOTVELOCITY", "FOLLOWTRAJECTORY", "BASEVELOCITY",
      "ARMSTATE", "PANTILTSTATE", "PANTILTCOMMAND"};
  return kNames.count(w) > 0;
}

std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path) {
  return std::make_unique<CarmenReader>(path);
}

}  // namespace cogmap::io
