// The MRPT rawlog reader and writer: the module libcogmap_io_mrpt.so
// (plugin_api.h), loaded by plugins.cc when a rawlog is read or written.
#include "cogmap/io/mrpt_rawlog.h"
#include "cogmap/io/log_lines.h"
#include "cogmap/io/plugin_api.h"

#include <mrpt/core/Clock.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <deque>
#include <filesystem>
#include <map>

#include "cogmap/core/error.h"

namespace cogmap::io {
namespace {

constexpr double kNoEchoSnapM = 1e-4;  // a float range within this of max range is max range

// One observation or action of the rawlog, flattened out of sensory frames,
// action collections and whole CRawlog objects.
struct Item {
  mrpt::obs::CObservation::Ptr obs;
  mrpt::obs::CAction::Ptr action;
  std::string other;        // class name of anything else
  bool from_frame = false;  // inside a CSensoryFrame or CActionCollection
  long entry = 0;           // 1-based index of the top-level object
};

// Counts the (uncompressed) bytes MRPT reads, so that an end of file inside
// an entry (truncated) can be told from one between entries.
class CountingStream : public mrpt::io::CStream {
 public:
  explicit CountingStream(mrpt::io::CFileGZInputStream& in) : in_(in) {}
  size_t Read(void* buffer, size_t count) override {
    const size_t n = in_.Read(buffer, count);
    read_ += n;
    return n;
  }
  size_t Write(const void*, size_t) override { throw std::runtime_error("read-only stream"); }
  uint64_t Seek(int64_t, CStream::TSeekOrigin) override { throw std::runtime_error("cannot seek"); }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return in_.getPosition(); }
  uint64_t read() const { return read_; }

 private:
  mrpt::io::CFileGZInputStream& in_;
  uint64_t read_ = 0;
};

class Entries {
 public:
  explicit Entries(const std::string& path) : path_(path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "cannot open: no such file");
    try {
      if (!file_.open(path)) throw InputError(path, 0, "cannot open");
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& e) {
      throw InputError(path, 0, std::string("cannot open (MRPT: ") + e.what() + ")");
    }
    size_ = static_cast<double>(std::filesystem::file_size(path, ec));
  }

  bool Next(Item* out) {
    while (pending_.empty()) {
      if (!ReadObject()) return false;
    }
    *out = std::move(pending_.front());
    pending_.pop_front();
    return true;
  }

  long entries() const { return entry_; }
  double progress() const {
    if (size_ <= 0) return 1.0;
    return std::clamp(static_cast<double>(file_.getPosition()) / size_, 0.0, 1.0);
  }

 private:
  bool ReadObject() {
    auto arch = mrpt::serialization::archiveFrom(counter_);
    const uint64_t before = counter_.read();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      arch >> obj;
    } catch (const mrpt::serialization::CExceptionEOF&) {
      if (counter_.read() == before) return false;  // a clean end between entries
      Fail("truncated: the file ends inside this entry");
    } catch (const std::bad_alloc&) {
      // (Read first in a child process with bounded memory: child_check.h.)
      Fail("a damaged entry: a count in it asks for more memory than such a file can need");
    } catch (const std::exception& e) {
      if (counter_.read() > before && file_.checkEOF()) Fail("truncated: the file ends inside this entry");
      std::string what = e.what();
      // (Control characters from a damaged class name would reach the terminal.)
      for (char& c : what)
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = c == '\n' ? ' ' : '?';
      // MRPT nests its exceptions: keep the innermost message.
      const auto msg = what.rfind("Message:");
      if (msg != std::string::npos) {
        what = what.substr(msg + 8);
        const auto loc = what.find("Location:");
        if (loc != std::string::npos) what = what.substr(0, loc);
        what = what.substr(std::min(what.find_first_not_of(' '), what.size()));
        while (!what.empty() && what.back() == ' ') what.pop_back();
      }
      Fail("not an MRPT rawlog entry this MRPT (2.x) can read: another format or another MRPT version (MRPT: " +
           what.substr(0, 400) + ")");
    }
    ++entry_;
    if (!obj) Fail("empty object");
    Flatten(obj, false);
    return true;
  }

  void Flatten(const mrpt::serialization::CSerializable::Ptr& obj, bool in_frame) {
    using namespace mrpt::obs;
    if (auto raw = std::dynamic_pointer_cast<CRawlog>(obj)) {
      for (size_t i = 0; i < raw->size(); ++i) Flatten(raw->getAsGeneric(i), false);
    } else if (auto acts = std::dynamic_pointer_cast<CActionCollection>(obj)) {
      for (size_t i = 0; i < acts->size(); ++i) pending_.push_back({nullptr, acts->get(i), "", true, entry_});
    } else if (auto sf = std::dynamic_pointer_cast<CSensoryFrame>(obj)) {
      for (const auto& o : *sf) pending_.push_back({o, nullptr, "", true, entry_});
    } else if (auto o = std::dynamic_pointer_cast<CObservation>(obj)) {
      pending_.push_back({o, nullptr, "", in_frame, entry_});
    } else {
      pending_.push_back({nullptr, nullptr, obj->GetRuntimeClass()->className, in_frame, entry_});
    }
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw InputError(path_ + ": entry " + std::to_string(entry_ + 1) + ": " + problem);
  }

  std::string path_;
  mutable mrpt::io::CFileGZInputStream file_;
  CountingStream counter_{file_};
  std::deque<Item> pending_;
  long entry_ = 0;
  double size_ = 0;
};

// "mrpt::obs::CObservationRange" -> "CObservationRange".
std::string ShortName(const std::string& class_name) {
  const auto p = class_name.rfind("::");
  return p == std::string::npos ? class_name : class_name.substr(p + 2);
}

double Seconds(const mrpt::Clock::time_point& t) { return mrpt::Clock::toDouble(t); }

double Yaw(const mrpt::math::TPose3D& p) { return p.yaw; }

struct SonarKey {
  std::string label;
  int id = 0;
  bool operator<(const SonarKey& o) const { return label != o.label ? label < o.label : id < o.id; }
};

class RawlogReader : public LogReader {
 public:
  RawlogReader(const std::string& path, const LogOpenOptions& options) : path_(path) {
    Discover();
    entries_ = std::make_unique<Entries>(path_);
  }

  bool Next(sensors::LogRecord* out) override {
    Item item;
    while (entries_->Next(&item)) {
      if (item.from_frame) frames_ = true;
      if (item.action) {
        auto move = std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(item.action);
        if (!move) {
          ++skipped_[ShortName(item.action->GetRuntimeClass()->className)];
          continue;
        }
        mrpt::poses::CPose2D inc = move->rawOdometryIncrementReading;
        try {
          inc = move->poseChange->getMeanVal();
        } catch (const std::exception&) {
          // no pose change PDF: the raw increment
        }
        pose_ = pose_.value_or(Pose2{}) * Pose2{inc.x(), inc.y(), inc.phi()};
        CheckOdometry(item);
        *out = {};
        out->time_s = Seconds(move->timestamp);
        out->odom = *pose_;
        return true;
      }
      if (!item.obs) {
        ++skipped_[ShortName(item.other)];
        continue;
      }
      const auto& obs = item.obs;
      if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs)) {
        pose_ = Pose2{odo->odometry.x(), odo->odometry.y(), odo->odometry.phi()};
        CheckOdometry(item);
        *out = {};
        out->time_s = Seconds(odo->timestamp);
        out->odom = *pose_;
        return true;
      }
      sensors::LogRecord r;
      if (auto range = std::dynamic_pointer_cast<mrpt::obs::CObservationRange>(obs)) {
        for (const auto& m : range->sensedData) {
          const int s = sonar_index_.at({range->sensorLabel, m.sensorID});
          r.ranges.push_back({s, Range(m.sensedDistance, robot_.sensors[s])});
        }
      } else if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs)) {
        const auto& [first, n] = laser_index_.at(scan->sensorLabel);
        if (static_cast<int>(scan->getScanSize()) != n)
          throw InputError(path_ + ": entry " + std::to_string(item.entry) + ": CObservation2DRangeScan '" +
                           scan->sensorLabel + "' has " + std::to_string(scan->getScanSize()) +
                           " ranges, its first scan had " + std::to_string(n));
        for (int i = 0; i < n; ++i) {
          const auto& q = robot_.sensors[first + i];
          r.ranges.push_back(
              {first + i, scan->getScanRangeValidity(i) ? Range(scan->getScanRange(i), q) : q.max_range_m});
        }
      } else {
        ++skipped_[ShortName(obs->GetRuntimeClass()->className)];
        continue;
      }
      if (!pose_) {
        if (!frames_) {
          ++skipped_["range observations before the first odometry"];
          continue;
        }
        pose_ = Pose2{};  // an actions-observations rawlog starts at the origin
      }
      if (r.ranges.empty()) continue;
      r.time_s = Seconds(obs->timestamp);
      r.odom = *pose_;
      *out = std::move(r);
      ++readings_;
      return true;
    }
    if (readings_ == 0)
      throw InputError(path_ + ": no range readings with a pose (" + std::to_string(odometry_) +
                       " odometry entries; range observations come before any odometry)");
    return false;
  }

  std::optional<sensors::RobotDescription> robot_hint() const override { return robot_; }
  std::map<std::string, long> skipped() const override { return skipped_; }
  double progress() const override { return entries_->progress(); }
  const std::string& path() const override { return path_; }
  std::vector<LogContent> contents() const override { return contents_; }

 private:
  // InputError naming the entry when the pose just read is not finite or absurdly far (PoseProblem).
  void CheckOdometry(const Item& item) const {
    if (const std::string problem = PoseProblem(*pose_); !problem.empty())
      throw InputError(path_ + ": entry " + std::to_string(item.entry) + ": odometry: " + problem);
  }
  static double Range(double r, const sensors::RangeSensor& q) {
    if (!std::isfinite(r) || r >= q.max_range_m - kNoEchoSnapM) return q.max_range_m;
    return std::max(r, 0.0);
  }

  // First pass: the sensors, and what the rawlog holds.
  void Discover() {
    Entries e(path_);
    std::map<std::string, long> counts;
    std::map<std::string, sensors::RobotDescription> lasers;
    std::map<SonarKey, sensors::RangeSensor> sonars;
    long odometry = 0;
    Item item;
    while (e.Next(&item)) {
      if (item.action) {
        ++counts[ShortName(item.action->GetRuntimeClass()->className)];
        odometry += std::dynamic_pointer_cast<mrpt::obs::CActionRobotMovement2D>(item.action) != nullptr;
        continue;
      }
      if (!item.obs) {
        ++counts[ShortName(item.other)];
        continue;
      }
      ++counts[ShortName(item.obs->GetRuntimeClass()->className)];
      if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(item.obs)) ++odometry;
      if (auto range = std::dynamic_pointer_cast<mrpt::obs::CObservationRange>(item.obs)) {
        for (const auto& m : range->sensedData) {
          SonarKey key{range->sensorLabel, m.sensorID};
          if (sonars.count(key)) continue;
          sensors::RangeSensor q;
          q.robot_from_sensor = {m.sensorPose.x, m.sensorPose.y, NormalizeAngle(Yaw(m.sensorPose))};
          q.beam_width_rad = range->sensorConeApperture;
          q.min_range_m = range->minSensorDistance;
          q.max_range_m = range->maxSensorDistance;
          q.kind = sensors::SensorKind::kSonar;
          if (!(q.max_range_m > 0))
            throw InputError(path_ + ": entry " + std::to_string(item.entry) + ": CObservationRange '" +
                             range->sensorLabel + "' has maxSensorDistance " + std::to_string(q.max_range_m));
          sonars[key] = q;
        }
      } else if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(item.obs)) {
        if (lasers.count(scan->sensorLabel)) continue;
        const size_t n = scan->getScanSize();
        if (n == 0)
          throw InputError(path_ + ": entry " + std::to_string(item.entry) + ": CObservation2DRangeScan '" +
                           scan->sensorLabel + "' without ranges");
        sensors::RobotDescription laser;
        const Pose2 at{scan->sensorPose.x(), scan->sensorPose.y(), scan->sensorPose.yaw()};
        for (size_t i = 0; i < n; ++i) {
          sensors::RangeSensor q;
          q.robot_from_sensor = at * Pose2{0, 0, scan->getScanAngle(i)};
          q.beam_width_rad = n > 1 ? scan->aperture / (n - 1) : DegToRad(0.5);
          q.min_range_m = 0.0;
          q.max_range_m = scan->maxRange;
          q.kind = sensors::SensorKind::kLaser;
          laser.sensors.push_back(q);
        }
        lasers[scan->sensorLabel] = laser;
      }
    }
    odometry_ = odometry;
    for (const auto& [label, laser] : lasers) {
      laser_index_[label] = {static_cast<int>(robot_.sensors.size()), static_cast<int>(laser.sensors.size())};
      for (const auto& q : laser.sensors) robot_.sensors.push_back(q);
    }
    for (const auto& [key, q] : sonars) {
      sonar_index_[key] = static_cast<int>(robot_.sensors.size());
      robot_.sensors.push_back(q);
    }
    std::string found;
    for (const auto& [name, n] : counts) found += (found.empty() ? "" : ", ") + std::to_string(n) + " " + name;
    if (robot_.sensors.empty())
      throw InputError(path_ + ": no range data: no CObservationRange or CObservation2DRangeScan (" +
                       (found.empty() ? std::string("no entries") : found) + ")");
    if (odometry == 0)
      throw InputError(path_ + ": no odometry: no CObservationOdometry or CActionRobotMovement2D (" + found + ")");
    robot_.name = !lasers.empty() && !sonars.empty() ? "mrpt-laser-sonar" : !lasers.empty() ? "mrpt-laser" : "mrpt-sonar";
    if (auto named = MatchingBuiltinRobot(robot_)) robot_ = *named;
    for (const auto& [name, n] : counts) {
      std::string use;
      if (name == "CObservationOdometry" || name == "CActionRobotMovement2D") use = "odometry";
      if (name == "CObservationRange") use = "sonar (" + std::to_string(sonars.size()) + " sensors)";
      if (name == "CObservation2DRangeScan") use = "laser (" + std::to_string(lasers.size()) + " scanners)";
      contents_.push_back({name, "MRPT class", n, use});
    }
  }

  std::string path_;
  std::unique_ptr<Entries> entries_;
  sensors::RobotDescription robot_;
  std::map<std::string, std::pair<int, int>> laser_index_;  // label -> first sensor, beams
  std::map<SonarKey, int> sonar_index_;
  std::optional<Pose2> pose_;
  bool frames_ = false;
  long readings_ = 0, odometry_ = 0;
  std::map<std::string, long> skipped_;
  std::vector<LogContent> contents_;
};

std::unique_ptr<LogReader> OpenRawlog(const std::string& path, const LogOpenOptions& options) {
  return std::make_unique<RawlogReader>(path, options);
}

long WriteRawlog(const std::string& path, const sensors::RobotDescription& robot,
                 const std::function<bool(sensors::LogRecord*)>& next) {
  const auto fans = LaserFans(robot);
  std::vector<int> fan_of(robot.sensors.size(), -1);
  for (size_t f = 0; f < fans.size(); ++f)
    for (int k = 0; k < fans[f].count; ++k) fan_of[fans[f].first + k] = static_cast<int>(f);
  const std::string tmp = path + ".partial";
  long records = 0;
  try {
    {
      mrpt::io::CFileGZOutputStream file;
      if (!file.open(tmp)) throw InputError(path, 0, "cannot write");
      auto arch = mrpt::serialization::archiveFrom(file);
      sensors::LogRecord r;
      while (next(&r)) {
        ++records;
        const auto stamp = mrpt::Clock::fromDouble(r.time_s);
        mrpt::obs::CObservationOdometry odo;
        odo.sensorLabel = "ODOMETRY";
        odo.timestamp = stamp;
        odo.odometry = mrpt::poses::CPose2D(r.odom.x, r.odom.y, r.odom.theta);
        arch << odo;
        if (r.ranges.empty()) continue;
        mrpt::obs::CObservationRange sonar;
        std::vector<mrpt::obs::CObservation2DRangeScan> scans(fans.size());
        std::vector<bool> used(fans.size(), false);
        for (const auto& q : r.ranges) {
          if (q.sensor < 0 || q.sensor >= static_cast<int>(robot.sensors.size()))
            throw InputError(path + ": record " + std::to_string(records) + ": reading of sensor " +
                             std::to_string(q.sensor) + " but robot '" + robot.name + "' has " +
                             std::to_string(robot.sensors.size()) + " sensors");
          const auto& s = robot.sensors[q.sensor];
          if (s.kind == sensors::SensorKind::kSonar) {
            if (sonar.sensedData.empty()) {
              sonar.sensorLabel = "SONAR";
              sonar.timestamp = stamp;
              sonar.minSensorDistance = static_cast<float>(s.min_range_m);
              sonar.maxSensorDistance = static_cast<float>(s.max_range_m);
              sonar.sensorConeApperture = static_cast<float>(s.beam_width_rad);
            }
            mrpt::obs::CObservationRange::TMeasurement m;
            m.sensorID = static_cast<uint16_t>(q.sensor);
            m.sensorPose = mrpt::math::TPose3D(s.robot_from_sensor.x, s.robot_from_sensor.y, 0.0,
                                               s.robot_from_sensor.theta, 0.0, 0.0);
            m.sensedDistance = static_cast<float>(q.range_m);
            sonar.sensedData.push_back(m);
            continue;
          }
          const int f = fan_of[q.sensor];
          auto& scan = scans[f];
          const LaserFan& fan = fans[f];
          if (!used[f]) {
            used[f] = true;
            const double span = (fan.count - 1) * fan.increment_rad;
            const auto& first = robot.sensors[fan.first].robot_from_sensor;
            scan.sensorLabel = f == 0 ? "LASER" : "LASER" + std::to_string(f + 1);
            scan.timestamp = stamp;
            scan.aperture = static_cast<float>(std::abs(span));
            scan.rightToLeft = span >= 0;
            scan.maxRange = static_cast<float>(s.max_range_m);
            scan.sensorPose = mrpt::poses::CPose3D(first.x, first.y, 0.0, fan.angle_min_rad + span / 2, 0.0, 0.0);
            scan.resizeScan(fan.count);
            for (int k = 0; k < fan.count; ++k) {
              scan.setScanRange(k, static_cast<float>(s.max_range_m));
              scan.setScanRangeValidity(k, false);
            }
          }
          const int k = q.sensor - fan.first;
          scan.setScanRange(k, static_cast<float>(q.range_m));
          scan.setScanRangeValidity(k, q.range_m < s.max_range_m);
        }
        if (!sonar.sensedData.empty()) arch << sonar;
        for (size_t f = 0; f < fans.size(); ++f)
          if (used[f]) arch << scans[f];
      }
      file.close();
    }
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw InputError(path, 0, "cannot write (" + ec.message() + ")");
  } catch (const InputError&) {
    std::remove(tmp.c_str());
    throw;
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw InputError(path, 0, std::string("cannot write the rawlog (MRPT: ") + e.what() + ")");
  }
  return records;
}

}  // namespace
}  // namespace cogmap::io

extern "C" __attribute__((visibility("default"))) const cogmap::io::plugin::MrptTable* cogmap_io_mrpt_table() {
  static const cogmap::io::plugin::MrptTable table{cogmap::io::plugin::kPluginAbi, COGMAP_VERSION,
                                                   &cogmap::io::OpenRawlog, &cogmap::io::WriteRawlog};
  return &table;
}
