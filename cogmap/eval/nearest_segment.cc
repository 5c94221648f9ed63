#include "cogmap/eval/nearest_segment.h"

#include <boost/geometry.hpp>
#include <boost/geometry/index/rtree.hpp>
#include <boost/function_output_iterator.hpp>
#include <limits>
#include <utility>

namespace cogmap::eval {
namespace {

namespace bg = boost::geometry;
namespace bgi = boost::geometry::index;
using BPoint = bg::model::point<double, 2, bg::cs::cartesian>;
using BBox = bg::model::box<BPoint>;
using Value = std::pair<BBox, int>;

}  // namespace

struct NearestSegment::Impl {
  std::vector<Segment2> segments;
  bgi::rtree<Value, bgi::rstar<16>> tree;
};

NearestSegment::NearestSegment(const std::vector<Segment2>& segments) : impl_(std::make_unique<Impl>()) {
  impl_->segments = segments;
  std::vector<Value> values;
  values.reserve(segments.size());
  for (size_t i = 0; i < segments.size(); ++i) {
    const Vec2 lo = segments[i].a.cwiseMin(segments[i].b), hi = segments[i].a.cwiseMax(segments[i].b);
    values.push_back({BBox(BPoint(lo.x(), lo.y()), BPoint(hi.x(), hi.y())), static_cast<int>(i)});
  }
  impl_->tree = bgi::rtree<Value, bgi::rstar<16>>(values);  // bulk loading (packing)
}

NearestSegment::~NearestSegment() = default;

double NearestSegment::Distance(const Vec2& p) const {
  const auto& tree = impl_->tree;
  const auto& segs = impl_->segments;
  if (tree.empty()) return std::numeric_limits<double>::infinity();
  const BPoint q(p.x(), p.y());
  // The segment of the nearest box bounds the answer: d0 >= the true distance.
  double best = std::numeric_limits<double>::infinity();
  tree.query(bgi::nearest(q, 1), boost::make_function_output_iterator([&](const Value& v) {
               best = PointSegmentDistance(p, segs[v.second].a, segs[v.second].b);
             }));
  // Every segment nearer than d0 has its box within d0 of p: check those.
  const BBox around(BPoint(p.x() - best, p.y() - best), BPoint(p.x() + best, p.y() + best));
  tree.query(bgi::intersects(around), boost::make_function_output_iterator([&](const Value& v) {
               best = std::min(best, PointSegmentDistance(p, segs[v.second].a, segs[v.second].b));
             }));
  return best;
}

}  // namespace cogmap::eval
