#pragma once
// Rooms and sequences built in code for the localize tests.
#include <cmath>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/angles.h"
#include "cogmap/core/geometry.h"

namespace cogmap::localize::testing {

// Closed rectangle (first vertex repeated) centred at 'c', rotated by 'angle_rad'.
inline Polyline Rectangle(const Vec2& c, double w, double h, double angle_rad) {
  const Pose2 pose{c.x(), c.y(), angle_rad};
  Polyline p = {{-w / 2, -h / 2}, {w / 2, -h / 2}, {w / 2, h / 2}, {-w / 2, h / 2}, {-w / 2, -h / 2}};
  for (auto& v : p) v = pose * v;
  return p;
}

// Closed regular polygon with 'n' edges.
inline Polyline RegularPolygon(int n, double radius, double angle_rad) {
  Polyline p;
  for (int i = 0; i <= n; ++i) {
    const double a = angle_rad + 2.0 * kPi * i / n;
    p.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  return p;
}

// A single straight edge from 'a' in direction 'angle_rad'.
inline Polyline Edge(const Vec2& a, double angle_rad, double length_m) {
  return {a, a + length_m * Vec2(std::cos(angle_rad), std::sin(angle_rad))};
}

// An ASR whose walls are given in the raw world frame; local frame = world.
inline asr::Asr AsrWithWorldWalls(std::vector<Polyline> walls) {
  asr::Asr a;
  a.id = 0;
  a.walls_local = std::move(walls);
  return a;
}

// A corridor of 'n' square rooms (4 m, centres 5 m apart along x, walls along
// the axes); the robot drives along y = 0 at true heading 0 and its odometry
// heading drifts by 'drift_per_room_rad' every 5 m (linearly). Each room's walls
// are mapped with the odometry pose at the room centre; each ASR's local frame
// is the raw pose where the robot entered it.
inline std::vector<asr::Asr> DriftingCorridor(int n, double drift_per_room_rad, double step_m = 0.05) {
  std::vector<asr::Asr> out;
  const double room_m = 5.0;
  Pose2 raw{-room_m / 2.0, 0.0, 0.0};
  const int steps_per_room = static_cast<int>(std::lround(room_m / step_m));
  for (int k = 0; k < n; ++k) {
    asr::Asr a;
    a.id = k;
    a.entry_pivot_m = raw.translation();
    a.world_from_local_raw = raw;
    Pose2 raw_at_centre;
    Pose2 true_at_centre;
    for (int i = 0; i < steps_per_room; ++i) {
      const double s = k * room_m + i * step_m;  // distance from the first entry
      const Pose2 truth{s - room_m / 2.0, 0.0, 0.0};
      if (i == steps_per_room / 2) {
        raw_at_centre = raw;
        true_at_centre = truth;
      }
      a.path.push_back(raw);
      a.true_path.push_back(truth);
      // Odometry: true step length, heading with the accumulated drift.
      const double drift = drift_per_room_rad * (s + step_m) / room_m;
      raw = Pose2{raw.x + step_m * std::cos(raw.theta), raw.y + step_m * std::sin(raw.theta), drift};
    }
    const Pose2 raw_from_true = raw_at_centre * true_at_centre.inverse();
    const Polyline room_true = Rectangle({k * room_m, 0.0}, 4.0, 4.0, 0.0);
    a.walls_local = {Transform(a.world_from_local_raw.inverse() * raw_from_true, room_true)};
    a.world_from_local_corrected = a.world_from_local_raw;
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace cogmap::localize::testing
