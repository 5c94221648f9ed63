#pragma once
#include <cstdint>
#include <vector>

#include "cogmap/core/floor_plan.h"
#include "cogmap/core/geometry.h"

namespace cogmap::sim {

// The nearest wall met by a ray.
struct RayHit {
  double distance_m = 0.0;  // along the ray from its origin
  int wall = -1;            // index into World::walls(); -1: nothing in range
  Vec2 normal{0, 0};        // unit normal of the wall, facing the ray's origin
  bool hit() const { return wall >= 0; }
};

// The walls of a floor plan in a uniform grid of segment buckets, so that ray
// casts (3D-DDA-style traversal of the buckets, exact ray-segment tests) and
// clearance queries only look at nearby walls, however many the building has.
class World {
 public:
  // 'bucket_m' <= 0 picks a bucket size from the extent of the walls (about
  // 1 m, coarser for huge maps so that the grid stays under ~4M buckets).
  explicit World(std::vector<Segment2> walls, double bucket_m = 0.0);

  const std::vector<Segment2>& walls() const { return walls_; }
  Vec2 min() const { return min_; }  // bounding box of the walls
  Vec2 max() const { return max_; }
  double bucket_m() const { return bucket_m_; }

  // Nearest wall along the ray from 'origin' in direction 'heading_rad' within
  // 'max_range_m'. Walls touching the origin (distance 0) count as hits.
  RayHit CastRay(const Vec2& origin, double heading_rad, double max_range_m) const;

  // Distance from 'p' to the nearest wall, or 'limit_m' if none is nearer
  // than 'limit_m' (the search is bounded by it).
  double Clearance(const Vec2& p, double limit_m) const;

  // True if the straight segment from 'a' to 'b' crosses or touches no wall.
  bool LineOfSight(const Vec2& a, const Vec2& b) const;

 private:
  template <typename Visit>
  void ForBucketsInBox(const Vec2& lo, const Vec2& hi, Visit&& visit) const;
  long BucketFlat(int ix, int iy) const { return static_cast<long>(iy) * nx_ + ix; }

  std::vector<Segment2> walls_;
  Vec2 min_{0, 0}, max_{0, 0};
  Vec2 origin_{0, 0};  // lower-left corner of bucket (0, 0)
  double bucket_m_ = 1.0;
  int nx_ = 0, ny_ = 0;
  std::vector<uint32_t> bucket_start_;  // CSR: walls of bucket b are
  std::vector<uint32_t> bucket_walls_;  // bucket_walls_[start[b] .. start[b+1])
};

// Exact intersection of the ray origin + t * dir (|dir| = 1, t >= 0) with the
// segment [a, b]. Returns t, or a negative value when they do not meet.
double RaySegmentDistance(const Vec2& origin, const Vec2& dir, const Vec2& a, const Vec2& b);

}  // namespace cogmap::sim
