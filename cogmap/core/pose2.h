#pragma once
#include <cmath>
#include <Eigen/Core>

#include "cogmap/core/angles.h"

namespace cogmap {

using Vec2 = Eigen::Vector2d;

// A rigid transform in the plane: metres and radians, counter-clockwise
// heading (REP-103). Read "world_from_robot" as the pose of the robot in the
// world: it maps robot-frame points into the world frame.
struct Pose2 {
  double x = 0.0;
  double y = 0.0;
  double theta = 0.0;

  Vec2 translation() const { return {x, y}; }

  // this * p: maps a point from the child frame into this frame (eq. 3.5).
  Vec2 operator*(const Vec2& p) const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {x + c * p.x() - s * p.y(), y + s * p.x() + c * p.y()};
  }
  // Composition: (this * other) maps other's child frame into this frame.
  Pose2 operator*(const Pose2& o) const {
    const Vec2 t = (*this) * o.translation();
    return {t.x(), t.y(), NormalizeAngle(theta + o.theta)};
  }
  Pose2 inverse() const {
    const double c = std::cos(theta), s = std::sin(theta);
    return {-(c * x + s * y), -(-s * x + c * y), NormalizeAngle(-theta)};
  }
};

// Rotation of 'p' by 'angle_rad' about 'pivot'.
inline Vec2 RotateAbout(const Vec2& p, const Vec2& pivot, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const Vec2 d = p - pivot;
  return pivot + Vec2(c * d.x() - s * d.y(), s * d.x() + c * d.y());
}

// Rotation of a whole pose about 'pivot'.
inline Pose2 RotateAbout(const Pose2& pose, const Vec2& pivot, double angle_rad) {
  const Vec2 t = RotateAbout(pose.translation(), pivot, angle_rad);
  return {t.x(), t.y(), NormalizeAngle(pose.theta + angle_rad)};
}

// A stream of poses re-integrated under a heading drift of rate_rad_per_m
// per metre driven: each pose's heading turns by rate x the distance driven
// so far, and its position follows the turned headings (the chord from the
// anchor turned by the mean drift over it). The distance is counted from an
// anchor that moves once the robot is step_m from it, so that centimetre
// jitter between records (a CARMEN log's interleaved odometry) does not count
// as driving. A positive rate adds a drift (DriftAdder, --add-drift-deg-per-
// m); its negative removes one (the mapper's pre-bend). Rate 0: the poses as
// they are. 'start': the raw position where the distance begins.
class DriftReintegration {
 public:
  DriftReintegration(double rate_rad_per_m, const Vec2& start, double step_m = 0.1)
      : rate_(rate_rad_per_m), step_m_(step_m), last_(start), at_(start) {}
  Pose2 operator()(const Pose2& raw) {
    if (rate_ == 0.0) return raw;
    const Vec2 d = raw.translation() - last_;
    const double ds = d.norm();
    const Vec2 at = at_ + RotateAbout(d, Vec2(0.0, 0.0), rate_ * (s_ + 0.5 * ds));
    const Pose2 out{at.x(), at.y(), NormalizeAngle(raw.theta + rate_ * (s_ + ds))};
    if (ds >= step_m_) {
      at_ = at;
      s_ += ds;
      last_ = raw.translation();
    }
    return out;
  }

 private:
  double rate_, step_m_;
  Vec2 last_, at_;  // the anchor's raw and re-integrated positions
  double s_ = 0.0;  // distance driven to the anchor
};

}  // namespace cogmap
