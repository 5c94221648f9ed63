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

}  // namespace cogmap
