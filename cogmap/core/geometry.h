#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "cogmap/core/pose2.h"

namespace cogmap {

struct Segment2 {
  Vec2 a;
  Vec2 b;
  double length() const { return (b - a).norm(); }
};

// An open chain of vertices (a wall run). A closed outline repeats its first
// vertex at the end.
using Polyline = std::vector<Vec2>;

// The z component of the 2D cross product a x b: positive when b turns
// counter-clockwise from a.
inline double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

// Whether the segments [p1, p2] and [q1, q2] cross: each meets the other
// strictly between its ends (parallel segments, and segments that only
// touch at an end, do not).
inline bool SegmentsCross(const Vec2& p1, const Vec2& p2, const Vec2& q1, const Vec2& q2) {
  const Vec2 r = p2 - p1, s = q2 - q1;
  const double den = Cross(r, s);
  if (std::abs(den) < 1e-12) return false;
  const double t = Cross(q1 - p1, s) / den;
  const double u = Cross(q1 - p1, r) / den;
  return t > 0.0 && t < 1.0 && u > 0.0 && u < 1.0;
}

// Distance from p to the segment [a, b].
inline double PointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  if (len2 <= 0.0) return (p - a).norm();
  const double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// Perpendicular distance from p to the infinite line through a and b.
inline double PointLineDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len = ab.norm();
  if (len <= 0.0) return (p - a).norm();
  return std::abs(ab.x() * (p.y() - a.y()) - ab.y() * (p.x() - a.x())) / len;
}

inline double PolylineLength(const Polyline& line) {
  double s = 0.0;
  for (size_t i = 1; i < line.size(); ++i) s += (line[i] - line[i - 1]).norm();
  return s;
}

// Segments of all polylines, in order.
std::vector<Segment2> ToSegments(const std::vector<Polyline>& lines);

// The convex hull of points: counter-clockwise, no repeated vertex, collinear
// points dropped (Andrew's monotone chain). Fewer than three distinct points
// come back as they are (sorted, unique).
std::vector<Vec2> ConvexHull(std::vector<Vec2> points);

// The signed area of a polygon (its vertices in order, not repeated):
// positive when counter-clockwise (the shoelace formula).
double SignedArea(const std::vector<Vec2>& ring);

// Applies 'pose' to every vertex.
Polyline Transform(const Pose2& pose, const Polyline& line);
std::vector<Polyline> Transform(const Pose2& pose, const std::vector<Polyline>& lines);

// The rigid move (rotation + translation, no scale) that maps the points
// 'from' onto 'to' (pairwise, equal sizes) with the least sum of squared
// distances: the 2D closed form of Horn / Umeyama. Identity when empty; a
// pure translation when the points of 'from' all coincide.
Pose2 AlignPoints(const std::vector<Vec2>& from, const std::vector<Vec2>& to);

}  // namespace cogmap
