#pragma once
// Exact distance from a point to the nearest of a set of segments, for the
// metrics that compare a map with the true walls. Boost.Geometry's R*-tree of
// the segments' bounding boxes answers two queries per point: the nearest box
// (its segment's distance d0 bounds the answer from above), then every box
// within d0 of the point (any nearer segment is among them): about log n per
// query however far the nearest wall is (a map that drifted 40 m from the
// truth costs what a good one costs).
#include <memory>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::eval {

class NearestSegment {
 public:
  explicit NearestSegment(const std::vector<Segment2>& segments);
  ~NearestSegment();
  NearestSegment(const NearestSegment&) = delete;
  NearestSegment& operator=(const NearestSegment&) = delete;
  // +inf when there are no segments.
  double Distance(const Vec2& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cogmap::eval
