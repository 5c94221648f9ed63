#pragma once
// Rooms and sequences built in code for the localize tests.
#include <cmath>
#include <random>
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

// Noise of the walls as mapped (sonar-like): each wall of a room is split into
// 'pieces' edges whose inner vertices are jittered, plus short clutter edges.
struct WallNoise {
  int pieces = 1;
  double vertex_sigma_m = 0.0;
  int clutter_edges = 0;
  double clutter_length_m = 0.4;
  unsigned seed = 1;
};

// The closed rectangle of Rectangle() with noisy walls and clutter.
inline std::vector<Polyline> NoisyRoom(const Vec2& c, double w, double h, const WallNoise& noise,
                                       std::mt19937& rng) {
  std::normal_distribution<double> jitter(0.0, noise.vertex_sigma_m);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Polyline corners = Rectangle(c, w, h, 0.0);
  Polyline outline;
  for (size_t i = 0; i + 1 < corners.size(); ++i) {
    for (int j = 0; j < noise.pieces; ++j) {
      Vec2 v = corners[i] + (corners[i + 1] - corners[i]) * (double(j) / noise.pieces);
      if (j > 0) v += Vec2(jitter(rng), jitter(rng));
      outline.push_back(v);
    }
  }
  outline.push_back(outline.front());
  std::vector<Polyline> walls = {outline};
  for (int i = 0; i < noise.clutter_edges; ++i) {
    const Vec2 a = c + Vec2((unit(rng) - 0.5) * w * 0.8, (unit(rng) - 0.5) * h * 0.8);
    walls.push_back(Edge(a, unit(rng) * 2.0 * kPi, noise.clutter_length_m));
  }
  return walls;
}

// A corridor of 'n' square rooms (4 m, centres 5 m apart along x, walls along
// the axes); the robot drives along y = 0 at true heading 0 and its odometry
// heading drifts by 'drift_per_room_rad' every 5 m (linearly). Each room's walls
// are mapped with the odometry pose at the room centre; each ASR's local frame
// is the raw pose where the robot entered it; its one exit is where it left.
inline std::vector<asr::Asr> DriftingCorridor(int n, double drift_per_room_rad, double step_m = 0.05,
                                              const WallNoise& noise = {}) {
  std::vector<asr::Asr> out;
  std::mt19937 rng(noise.seed);
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
    const auto room_true = NoisyRoom({k * room_m, 0.0}, 4.0, 4.0, noise, rng);
    a.walls_local = Transform(a.world_from_local_raw.inverse() * raw_from_true, room_true);
    a.exits.push_back({raw.translation(), 0.9, k, k + 1});  // the door it leaves by
    a.world_from_local_corrected = a.world_from_local_raw;
    out.push_back(std::move(a));
  }
  return out;
}

}  // namespace cogmap::localize::testing
