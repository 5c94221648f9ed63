#include "cogmap/io/carmen_log.h"


#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/io/log_lines.h"

namespace cogmap::io {
namespace {

constexpr double kSickNoReturnM = 81.9;       // SICK LMS reports 8191 cm for no return
constexpr double kMinNoReturnCodeM = 20.0;    // a largest reading at least this far is the code
constexpr double kMissingTimeS = 1e-9;        // smaller timestamps are "no timestamp"
constexpr double kSonarMaxM = 5.0;            // Pioneer sonar range (CARMEN's SONAR has no max)
constexpr long kMaxCount = 100000;            // more beams or sonars than this is absurd

// One range device of the log: a laser (one message type) or the sonar ring.
struct Device {
  std::string message;      // "FLASER", "RAWLASER1", "SONAR", ...
  bool present = false;     // seen in the log (and not shadowed)
  bool shadowed = false;    // RAWLASERk whose scans a FLASER/RLASER/ROBOTLASERk carries with poses
  int beams = 0;
  double max_seen_m = 0.0;
  double param_max_m = 0.0;
  int first_sensor = 0;
  // From the first message: ROBOTLASERk / RAWLASERk geometry, the sonar ring.
  double start_rad = 0.0, res_rad = 0.0, max_range_m = 0.0, cone_rad = 0.0;
  Pose2 robot_from_laser;
  std::vector<Pose2> robot_from_sonar;
};

// The devices in robot sensor order.
enum DeviceId { kFront, kRear, kRobotLaser1, kRobotLaser2, kRaw1, kRaw2, kRaw3, kRaw4, kSonar, kDevices };
const char* const kDeviceMessages[kDevices] = {"FLASER",    "RLASER",    "ROBOTLASER1", "ROBOTLASER2", "RAWLASER1",
                                               "RAWLASER2", "RAWLASER3", "RAWLASER4",   "SONAR"};

int DeviceOf(std::string_view message) {
  for (int i = 0; i < kDevices; ++i)
    if (message == kDeviceMessages[i]) return i;
  return -1;
}

// Whether the reading written as 't' may be larger than 'max', the largest
// so far: a plain decimal ("2.31", "81") with fewer digits before its point
// than max has is smaller than it (below 10^digits <= max), and is not
// parsed. Anything else is parsed (a malformed reading fails as it would).
bool MayExceed(std::string_view t, double max) {
  if (!(max >= 1.0)) return true;
  int digits = 0, all_digits = 0, max_digits = 0;
  bool point = false;
  for (char c : t) {
    if (c == '.' && !point) {
      point = true;
    } else if (c >= '0' && c <= '9') {
      ++all_digits;
      if (!point) ++digits;
    } else {
      return true;
    }
  }
  if (all_digits == 0) return true;
  for (double m = max; m >= 1.0; m /= 10.0) ++max_digits;
  return digits >= max_digits;
}

double MaxRange(const Device& l) {
  if (l.param_max_m > 0) return l.param_max_m;
  if (l.max_seen_m >= kMinNoReturnCodeM) return l.max_seen_m;
  return kSickNoReturnM;
}


class CarmenReader : public LogReader {
 public:
  explicit CarmenReader(const std::string& path)
      : spool_(path == kStdinPath ? std::make_unique<StdinCopy>() : nullptr),
        open_path_(spool_ ? spool_->path() : path),
        src_(open_path_, spool_ ? std::string(kStdinName) : path) {
    for (int i = 0; i < kDevices; ++i) dev_[i].message = kDeviceMessages[i];
    PreScan();
    int next = 0;
    for (Device& d : dev_) {
      d.first_sensor = next;
      if (d.present) next += d.beams;
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
        ++odometry_;
        return Keep(out);
      }
      if (f[0] == "TRUEPOS") {
        Expect(f, 10, "TRUEPOS true_x true_y true_theta odom_x odom_y odom_theta timestamp host logger_timestamp");
        *out = {};
        out->truth = Pose(f, 1, "true_");
        out->odom = Pose(f, 4, "odom_");
        out->time_s = Time(f, 7, 9);
        ++odometry_;
        return Keep(out);
      }
      const int id = DeviceOf(f[0]);
      if (id == kFront || id == kRear) {
        ReadOldLaser(f, dev_[id], out);
        return Keep(out);
      }
      if (id == kRobotLaser1 || id == kRobotLaser2) {
        ReadRobotLaser(f, dev_[id], out);
        return Keep(out);
      }
      if (id >= kRaw1 && id <= kRaw4) {
        if (ReadRawLaser(f, dev_[id], out)) return true;
        continue;
      }
      if (id == kSonar) {
        if (ReadSonar(f, dev_[id], out)) return true;
        continue;
      }
      if (f[0] == "PARAM") {
        if (f.size() < 3) Fail("PARAM: expected 'PARAM name value'");
        continue;
      }
      const std::string name(f[0]);
      if (!IsCarmenMessageName(name))
        Fail("unknown message type '" + name.substr(0, 40) +
             "' (not a CARMEN message cogmap knows; docs/log-format.md lists them)");
      ++skipped_[name];  // a CARMEN message without range data or pose (NEFF, SYNC, GPS...)
    }
    if (readings_ == 0) {
      std::string problem = "empty log: no range readings (" + std::to_string(odometry_) +
                            " odometry messages, no laser or sonar message";
      for (const auto& [name, n] : skipped_) problem += "; skipped " + std::to_string(n) + " " + name;
      throw InputError(src_.path(), src_.line_number(), problem + ")");
    }
    return false;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  std::map<std::string, long> skipped() const override { return skipped_; }
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
  long Count(const std::vector<std::string_view>& f, size_t i, const std::string& what) const {
    if (f.size() <= i) Fail(std::string(f[0]) + ": message cut short before the " + what);
    const long n = ParseCount(f[i], src_.path(), src_.line_number(), what);
    if (n > kMaxCount) Fail(what + " " + std::to_string(n) + " is absurd");
    return n;
  }
  Pose2 Pose(const std::vector<std::string_view>& f, size_t i, const std::string& prefix) const {
    return CheckPosition({Num(f[i], prefix + "x"), Num(f[i + 1], prefix + "y"), Num(f[i + 2], prefix + "theta")},
                         src_.path(), src_.line_number(), prefix + "pose");
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
  // Remembers the record's pose for the messages without one (RAWLASER, SONAR).
  bool Keep(const sensors::LogRecord* r) {
    last_odom_ = r->odom;
    last_truth_ = r->truth;
    have_pose_ = true;
    return true;
  }
  void CheckBeams(const std::vector<std::string_view>& f, long n, const Device& d, const char* what) const {
    if (n != d.beams)
      Fail(std::string(f[0]) + " with " + std::to_string(n) + " " + what + ", but the first one had " +
           std::to_string(d.beams));
  }
  void ReadRanges(const std::vector<std::string_view>& f, size_t first, int n, int sensor0,
                  sensors::LogRecord* out, const char* what = "beam ") {
    out->ranges.resize(n);
    for (int i = 0; i < n; ++i) {
      const double r = Num(f[first + i], "range");
      if (!RangeAccepted(r)) CheckRange(r, src_.path(), src_.line_number(), what + std::to_string(i));
      out->ranges[i] = {sensor0 + i, r};
    }
    readings_ += n;
  }

  void ReadOldLaser(const std::vector<std::string_view>& f, const Device& l, sensors::LogRecord* out) {
    if (f.size() < 2) Fail(std::string(f[0]) + ": missing the beam count");
    const long n = Count(f, 1, "beam count");
    Expect(f, 11 + n,
           "n r1..rn x y theta odom_x odom_y odom_theta timestamp host logger_timestamp with n = " +
               std::to_string(n));
    CheckBeams(f, n, l, "beams");
    *out = {};
    ReadRanges(f, 2, static_cast<int>(n), l.first_sensor, out);
    out->truth = Pose(f, 2 + n, "");
    out->odom = Pose(f, 5 + n, "odom_");
    out->time_s = Time(f, 8 + n, 10 + n);
  }

  // ROBOTLASERk type start fov res max acc mode n r.. m e.. laser(3) robot(3)
  // tv rv fwd side turn timestamp host logger_timestamp.
  void ReadRobotLaser(const std::vector<std::string_view>& f, const Device& l, sensors::LogRecord* out) {
    const std::string name(f[0]);
    if (f.size() < 10) Fail(name + ": too few fields");
    const long n = Count(f, 8, "beam count");
    if (f.size() < 10 + static_cast<size_t>(n)) Fail(name + ": too few fields for the beams");
    const long m = Count(f, 9 + n, "remission count");
    Expect(f, 24 + n + m, name + " with " + std::to_string(n) + " beams and " + std::to_string(m) +
                              " remissions");
    CheckBeams(f, n, l, "beams");
    *out = {};
    ReadRanges(f, 9, static_cast<int>(n), l.first_sensor, out);
    const size_t k = 10 + n + m;
    Pose(f, k, "laser_");
    out->odom = Pose(f, k + 3, "robot_");
    out->time_s = Time(f, k + 11, k + 13);
  }

  // RAWLASERk type start fov res max acc mode n r.. m e.. timestamp host
  // logger_timestamp: no pose; the record is at the latest odometry pose.
  bool ReadRawLaser(const std::vector<std::string_view>& f, const Device& l, sensors::LogRecord* out) {
    const std::string name(f[0]);
    if (f.size() < 10) Fail(name + ": too few fields");
    const long n = Count(f, 8, "beam count");
    if (f.size() < 10 + static_cast<size_t>(n)) Fail(name + ": too few fields for the beams");
    const long m = Count(f, 9 + n, "remission count");
    Expect(f, 13 + n + m, name + " with " + std::to_string(n) + " beams and " + std::to_string(m) +
                              " remissions: type start_angle fov resolution max_range accuracy remission_mode"
                              " n r1..rn m e1..em timestamp host logger_timestamp");
    if (l.shadowed) {
      ++skipped_[name + " (the same scans as " + (name == "RAWLASER1" ? "FLASER/ROBOTLASER1" : "RLASER/ROBOTLASER2") +
                 ", which carry poses)"];
      return false;
    }
    CheckBeams(f, n, l, "beams");
    const double t = Time(f, 10 + n + m, 12 + n + m);
    if (!have_pose_) {
      ++skipped_[name + " (before the first odometry: no pose)"];
      return false;
    }
    *out = {};
    ReadRanges(f, 9, static_cast<int>(n), l.first_sensor, out);
    out->odom = last_odom_;
    out->truth = last_truth_;
    out->time_s = t;
    return true;
  }

  // SONAR cone_angle n r1..rn (x y theta)*n timestamp host logger_timestamp:
  // no pose; the record is at the latest odometry pose.
  bool ReadSonar(const std::vector<std::string_view>& f, const Device& d, sensors::LogRecord* out) {
    const long n = Count(f, 2, "sonar count");
    Expect(f, 6 + 4 * n,
           "SONAR cone_angle n r1..rn x1 y1 theta1 .. xn yn thetan timestamp host logger_timestamp with n = " +
               std::to_string(n));
    const double cone = Num(f[1], "cone_angle");
    if (!(cone > 0 && cone <= 2 * kPi))
      Fail("SONAR: cone_angle " + std::string(f[1]) + " must be in (0, 2 pi] radians");
    CheckBeams(f, n, d, "sonars");
    for (long i = 0; i < 3 * n; ++i) Num(f[3 + n + i], "sonar offset");
    const double t = Time(f, 3 + 4 * n, 5 + 4 * n);
    if (!have_pose_) {
      ++skipped_["SONAR (before the first odometry: no pose)"];
      return false;
    }
    *out = {};
    ReadRanges(f, 3, static_cast<int>(n), d.first_sensor, out, "sonar ");
    out->odom = last_odom_;
    out->truth = last_truth_;
    out->time_s = t;
    return true;
  }

  // One streaming pass at opening: PARAMs, which devices, their beam counts,
  // geometry and largest readings. Lines it cannot parse are left for Next()
  // to report.
  void PreScan() {
    LineSource scan(open_path_, src_.path());
    const std::string& path = src_.path();
    std::string line;
    while (scan.Next(&line)) {
      // Only PARAMs and range messages matter here: the others (ODOM, most
      // of a log's lines) are not split.
      const size_t b = line.find_first_not_of(" \t");
      if (b == std::string::npos) continue;
      const std::string_view head = std::string_view(line).substr(b, line.find_first_of(" \t", b) - b);
      if (head != "PARAM" && DeviceOf(head) < 0) continue;
      const auto f = SplitFields(line);
      try {
        auto num = [&](size_t i) { return ParseNumber(f.at(i), path, 0, "x"); };
        const int id = DeviceOf(f[0]);
        if (f[0] == "PARAM" && f.size() >= 3) {
          const std::string name(f[1]);
          if (name == "robot_front_laser_max" || name == "laser_front_laser_max_range") dev_[kFront].param_max_m = num(2);
          if (name == "robot_rear_laser_max" || name == "laser_rear_laser_max_range") dev_[kRear].param_max_m = num(2);
          if (name == "robot_frontlaser_offset") front_offset_m_ = num(2);
          if (name == "robot_rearlaser_offset") rear_offset_m_ = num(2);
        } else if ((id == kFront || id == kRear) && f.size() >= 2) {
          Device& l = dev_[id];
          const long n = ParseCount(f[1], path, 0, "n");
          // A hostile count (FLASER 30000000) must not size the robot: only a
          // whole message counts; Next() reports the others with their line.
          if (n > kMaxCount || f.size() != 11 + static_cast<size_t>(n)) continue;
          if (!l.present) {
            l.present = true;
            l.beams = static_cast<int>(n);
          }
          for (long i = 0; i < n && 2 + static_cast<size_t>(i) < f.size(); ++i)
            if (MayExceed(f[2 + i], l.max_seen_m)) l.max_seen_m = std::max(l.max_seen_m, num(2 + i));
        } else if (id >= kRobotLaser1 && id <= kRaw4 && f.size() >= 10 && !dev_[id].present) {
          const long n = ParseCount(f[8], path, 0, "n");
          if (n > kMaxCount || f.size() < 10 + static_cast<size_t>(n)) continue;
          const long m = ParseCount(f[9 + n], path, 0, "m");
          if (m > kMaxCount) continue;
          const bool robot = id <= kRobotLaser2;
          if (f.size() != (robot ? 24 : 13) + static_cast<size_t>(n + m)) continue;
          Device& l = dev_[id];
          l.start_rad = num(2);
          l.res_rad = num(4);
          l.max_range_m = num(5);
          if (robot) {
            const size_t k = 10 + n + m;
            const Pose2 laser{num(k), num(k + 1), num(k + 2)};
            const Pose2 robot_pose{num(k + 3), num(k + 4), num(k + 5)};
            l.robot_from_laser = robot_pose.inverse() * laser;
          }
          for (long i = 0; i < n; ++i)
            if (MayExceed(f[9 + i], l.max_seen_m)) l.max_seen_m = std::max(l.max_seen_m, num(9 + i));
          l.beams = static_cast<int>(n);
          l.present = true;
        } else if (id == kSonar && f.size() >= 3) {
          Device& d = dev_[kSonar];
          const long n = ParseCount(f[2], path, 0, "n");
          if (n > kMaxCount || f.size() != 6 + 4 * static_cast<size_t>(n)) continue;
          if (!d.present) {
            d.cone_rad = num(1);
            for (long i = 0; i < n; ++i)
              d.robot_from_sonar.push_back({num(3 + n + 3 * i), num(4 + n + 3 * i), num(5 + n + 3 * i)});
            d.beams = static_cast<int>(n);
            d.present = true;
          }
          for (long i = 0; i < n; ++i)
            if (MayExceed(f[3 + i], d.max_seen_m)) d.max_seen_m = std::max(d.max_seen_m, num(3 + i));
        }
      } catch (const std::exception&) {
        // Reported with its line number when Next() reaches it.
      }
    }
    // The raw scans of a laser whose scans the log also has with poses.
    for (int raw : {kRaw1, kRaw2}) {
      const bool posed = raw == kRaw1 ? dev_[kFront].present || dev_[kRobotLaser1].present
                                      : dev_[kRear].present || dev_[kRobotLaser2].present;
      if (dev_[raw].present && posed) {
        dev_[raw].present = false;
        dev_[raw].shadowed = true;
      }
    }
  }

  void BuildRobot() {
    bool laser = false;
    for (int id : {kFront, kRear}) {
      const Device& l = dev_[id];
      if (!l.present || l.beams < 1) continue;
      laser = true;
      sensors::LaserOptions o;
      o.beams = l.beams;
      o.fov_rad = CarmenLaserFov(l.beams);
      o.max_range_m = MaxRange(l);
      o.min_range_m = 0.0;
      auto scan = sensors::MakeLaser(o);
      for (auto& s : scan.sensors) {
        if (id == kRear) {
          s.robot_from_sensor.theta = NormalizeAngle(s.robot_from_sensor.theta + kPi);
          s.robot_from_sensor.x = -rear_offset_m_;
        } else {
          s.robot_from_sensor.x = front_offset_m_;
        }
        robot_.sensors.push_back(s);
      }
    }
    for (int id = kRobotLaser1; id <= kRaw4; ++id) {
      const Device& l = dev_[id];
      if (!l.present || l.beams < 1) continue;
      laser = true;
      // RAWLASER has no mount: laser 1 is CARMEN's front laser, laser 2 its
      // rear one (facing back), lasers 3 and 4 at the robot's centre.
      Pose2 mount = l.robot_from_laser;
      if (id == kRaw1) mount = Pose2{front_offset_m_, 0.0, 0.0};
      if (id == kRaw2) mount = Pose2{-rear_offset_m_, 0.0, kPi};
      if (id == kRaw3 || id == kRaw4) mount = Pose2{};
      for (int i = 0; i < l.beams; ++i) {
        sensors::RangeSensor s;
        s.robot_from_sensor = mount * Pose2{0, 0, l.start_rad + i * l.res_rad};
        s.robot_from_sensor.theta = NormalizeAngle(s.robot_from_sensor.theta);
        s.beam_width_rad = l.res_rad > 0 ? l.res_rad : DegToRad(1.0);
        s.min_range_m = 0.0;
        s.max_range_m = l.max_range_m > 0 ? l.max_range_m : MaxRange(l);
        s.kind = sensors::SensorKind::kLaser;
        robot_.sensors.push_back(s);
      }
    }
    const Device& sonar = dev_[kSonar];
    if (sonar.present) {
      for (const Pose2& p : sonar.robot_from_sonar) {
        sensors::RangeSensor s;  // min range: the sonar default
        s.robot_from_sensor = p;
        s.beam_width_rad = sonar.cone_rad > 0 && sonar.cone_rad <= 2 * kPi ? sonar.cone_rad : s.beam_width_rad;
        s.max_range_m = std::max(kSonarMaxM, sonar.max_seen_m);
        s.kind = sensors::SensorKind::kSonar;
        robot_.sensors.push_back(s);
      }
    }
    robot_.name = sonar.present ? (laser ? "carmen-laser-sonar" : "carmen-sonar") : "carmen-laser";
  }

  std::unique_ptr<StdinCopy> spool_;  // standard input's copy (the reader needs two passes)
  std::string open_path_;
  LineSource src_;
  Device dev_[kDevices];
  double front_offset_m_ = 0.0, rear_offset_m_ = 0.0;
  sensors::RobotDescription robot_;
  double last_time_ = 0.0;
  long readings_ = 0;
  long odometry_ = 0;
  Pose2 last_odom_;
  std::optional<Pose2> last_truth_;
  bool have_pose_ = false;
  std::map<std::string, long> skipped_;
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
      "ARMSTATE", "PANTILTSTATE", "PANTILTCOMMAND", "ARM", "NMEAGGA", "NMEARMC", "VELOCITY", "GLOBALPOS"};
  return kNames.count(w) > 0;
}

std::unique_ptr<LogReader> OpenCarmenLog(const std::string& path) {
  return std::make_unique<CarmenReader>(path);
}

}  // namespace cogmap::io
