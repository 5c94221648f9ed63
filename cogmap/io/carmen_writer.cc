#include "cogmap/io/carmen_writer.h"

#include <charconv>
#include <cmath>

#include "cogmap/core/error.h"
#include "cogmap/core/angles.h"

namespace cogmap::io {
namespace {

// Beams of one scanner are "evenly spaced" when each step differs from the
// first by less than this (well below a float's resolution of a degree).
constexpr double kStepToleranceRad = 1e-9;

void Append(std::string* s, double v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  s->push_back(' ');
  s->append(buf, r.ptr);
}

}  // namespace

CarmenLogWriter::CarmenLogWriter(std::ostream& out, const sensors::RobotDescription& robot, const std::string& source)
    : out_(out), robot_(robot), source_(source) {
  const auto& s = robot_.sensors;
  if (s.empty()) throw InputError(source_, 0, "robot '" + robot_.name + "' has no sensors to write");
  bool all_sonar = true, all_laser = true;
  for (const auto& q : s) {
    all_sonar = all_sonar && q.kind == sensors::SensorKind::kSonar;
    all_laser = all_laser && q.kind == sensors::SensorKind::kLaser;
  }
  auto refuse = [&](const std::string& why) {
    throw InputError(source_, 0, "cannot write robot '" + robot_.name + "' as a CARMEN log: " + why);
  };
  if (all_sonar) {
    sonar_ = true;
    for (const auto& q : s)
      if (q.beam_width_rad != s[0].beam_width_rad)
        refuse("its sonars have different beam widths (CARMEN's SONAR has one cone angle)");
  } else if (all_laser) {
    // One scanner: every beam from the same point, at equal angle steps, with
    // one maximum range (ROBOTLASER1's start, resolution and max_range).
    laser_mount_ = {s[0].robot_from_sensor.x, s[0].robot_from_sensor.y, 0.0};
    laser_start_rad_ = s[0].robot_from_sensor.theta;
    if (s.size() > 1) laser_step_rad_ = NormalizeAngle(s[1].robot_from_sensor.theta - s[0].robot_from_sensor.theta);
    for (size_t i = 0; i < s.size(); ++i) {
      const auto& p = s[i].robot_from_sensor;
      if (p.x != laser_mount_.x || p.y != laser_mount_.y)
        refuse("its laser beams start at different points (more than one scanner)");
      const double want = laser_start_rad_ + static_cast<double>(i) * laser_step_rad_;
      if (std::abs(NormalizeAngle(p.theta - want)) > kStepToleranceRad)
        refuse("its laser beams are not at equal angle steps (beam " + std::to_string(i) + ")");
      if (s[i].max_range_m != s[0].max_range_m) refuse("its laser beams have different maximum ranges");
    }
  } else {
    refuse("it mixes sonars and lasers (write them as two logs)");
  }
  out_ << "# CARMEN Logfile\n# written by cogmap convert from " << source_ << "\n# robot " << robot_.name << "\n";
}

void CarmenLogWriter::Write(const sensors::LogRecord& r) {
  const auto& s = robot_.sensors;
  const size_t n = s.size();
  if (!r.ranges.empty()) {
    bool whole = r.ranges.size() == n;
    for (size_t i = 0; whole && i < n; ++i) whole = r.ranges[i].sensor == static_cast<int>(i);
    if (!whole)
      throw InputError(source_, 0,
                       "record " + std::to_string(records_ + 1) + " has " + std::to_string(r.ranges.size()) +
                           " readings, not one of each of the " + std::to_string(n) + " " +
                           (sonar_ ? "sonars" : "beams") + " in sensor order: CARMEN's " +
                           (sonar_ ? "SONAR" : "ROBOTLASER1") + " message carries them all at once");
  }
  buf_.clear();
  auto stamp = [&] {
    Append(&buf_, r.time_s);
    buf_ += " cogmap";
    Append(&buf_, r.time_s);
    buf_.push_back('\n');
  };
  auto pose = [&](const Pose2& p) {
    Append(&buf_, p.x);
    Append(&buf_, p.y);
    Append(&buf_, p.theta);
  };
  if (r.truth) {
    buf_ += "TRUEPOS";
    pose(*r.truth);
    pose(r.odom);
  } else {
    buf_ += "ODOM";
    pose(r.odom);
    buf_ += " 0 0 0";
  }
  stamp();
  if (!r.ranges.empty() && sonar_) {
    buf_ += "SONAR";
    Append(&buf_, s[0].beam_width_rad);
    buf_ += ' ' + std::to_string(n);
    for (const auto& q : r.ranges) Append(&buf_, q.range_m);
    for (const auto& q : s) pose(q.robot_from_sensor);
    stamp();
  } else if (!r.ranges.empty()) {
    // type 0, fov as CARMEN counts it (first to last beam), accuracy 0,
    // remission mode 0 and no remissions.
    buf_ += "ROBOTLASER1 0";
    Append(&buf_, laser_start_rad_);
    Append(&buf_, laser_step_rad_ * static_cast<double>(n - 1));
    Append(&buf_, laser_step_rad_);
    Append(&buf_, s[0].max_range_m);
    buf_ += " 0 0 " + std::to_string(n);
    for (const auto& q : r.ranges) Append(&buf_, q.range_m);
    buf_ += " 0";
    pose(r.odom * laser_mount_);
    pose(r.odom);
    buf_ += " 0 0 0 0 0";
    stamp();
  }
  out_ << buf_;
  ++records_;
}

}  // namespace cogmap::io
