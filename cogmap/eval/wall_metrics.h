#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::eval {

// Wall metrics against ground truth (issue 4, reused by the map and
// localization issues). Everything in one world frame, metres.
struct WallMetricsOptions {
  double sample_step_m = 0.05;    // spacing of the points sampled along walls
  double recall_within_m = 0.2;   // a seen true-wall point counts when a map wall is this close
  double sensor_range_m = 5.0;    // a true-wall point is seeable within this of the true path
  double path_step_m = 0.1;       // the true path is thinned to poses this far apart
  double sight_tolerance_m = 1e-3;  // a sight line ends this short of the wall point it looks at
};

// Points every 'step_m' along a segment, both ends included (at least the two
// ends; a zero-length segment gives its one point).
std::vector<Vec2> SampleSegment(const Segment2& s, double step_m);

struct PrecisionStats {
  int64_t samples = 0;  // points sampled along the map's walls
  double mean_m = 0.0;  // mean distance to the nearest true wall
  double p95_m = 0.0;   // 95th percentile (nearest rank)
  double max_m = 0.0;
};

// Distance from points sampled along the map walls to the nearest true wall.
// No map walls: samples = 0 and the distances 0. No true walls: infinite.
PrecisionStats WallPrecision(const std::vector<Polyline>& map_walls,
                             const std::vector<Segment2>& true_walls,
                             const WallMetricsOptions& options = {});

struct RecallStats {
  double seeable_length_m = 0.0;  // true-wall length within range and sight of the path
  double found_length_m = 0.0;    // of which a map wall lies within recall_within_m
  double recall() const { return seeable_length_m > 0.0 ? found_length_m / seeable_length_m : 0.0; }
  int64_t samples = 0;            // true-wall points tested
  int64_t seeable_samples = 0;
};

// True when the straight line from 'from' to 'to' (shortened by 'tolerance_m'
// at 'to') crosses no wall.
bool ClearLineOfSight(const Vec2& from, const Vec2& to, const std::vector<Segment2>& walls,
                      double tolerance_m);

// The fraction of the length of the true walls that the robot could have
// seen (a sample point within sensor_range_m of some pose of the true path with
// a clear line of sight) which lies within recall_within_m of a map wall. Each
// sample stands for the length of wall around it (step, halved at the ends).
RecallStats WallRecall(const std::vector<Polyline>& map_walls, const std::vector<Segment2>& true_walls,
                       const std::vector<Vec2>& true_path, const WallMetricsOptions& options = {});

// Drops path points closer than step_m to the previous kept one (first and
// last kept).
std::vector<Vec2> ThinPath(const std::vector<Vec2>& path, double step_m);

}  // namespace cogmap::eval
