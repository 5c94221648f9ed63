// NearestSegment against brute force: exact equality on random segments and
// points near and far (the case the old ring search paid for).
#include "cogmap/eval/nearest_segment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace cogmap::eval {
namespace {

TEST(NearestSegment, EqualsBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(0.0, 500.0), len(-3.0, 3.0), far(-200.0, 700.0);
  std::vector<Segment2> segs;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 a(pos(rng), pos(rng) * 0.02);  // a long thin building, as a corridor of rooms
    segs.push_back({a, a + Vec2(len(rng), len(rng))});
  }
  segs.push_back({Vec2(10, 10), Vec2(10, 10)});  // a point-like segment
  const NearestSegment index(segs);
  for (int k = 0; k < 3000; ++k) {
    const Vec2 p(far(rng), far(rng) * 0.3);
    double want = std::numeric_limits<double>::infinity();
    for (const auto& s : segs) want = std::min(want, PointSegmentDistance(p, s.a, s.b));
    ASSERT_EQ(index.Distance(p), want) << p.transpose();
  }
}

TEST(NearestSegment, KnownDistancesAndEmpty) {
  const NearestSegment index({{Vec2(0, 0), Vec2(10, 0)}, {Vec2(0, 5), Vec2(10, 5)}});
  EXPECT_DOUBLE_EQ(index.Distance(Vec2(5, 1)), 1.0);
  EXPECT_DOUBLE_EQ(index.Distance(Vec2(5, 3)), 2.0);
  EXPECT_DOUBLE_EQ(index.Distance(Vec2(13, 9)), 5.0);  // from the end (10, 5)
  EXPECT_TRUE(std::isinf(NearestSegment({}).Distance(Vec2(0, 0))));
}

}  // namespace
}  // namespace cogmap::eval
