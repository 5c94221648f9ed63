#include "cogmap/vectorize/orientation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cogmap::vectorize {
namespace {

// Points every 'step' along the four walls of a w x h rectangle centred at the
// origin, rotated by 'angle', optionally jittered.
std::vector<Vec2> Room(double w, double h, double angle, double step = 1.0, double jitter = 0.0,
                       uint32_t seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, jitter);
  std::vector<Vec2> out;
  const Vec2 corners[5] = {{-w / 2, -h / 2}, {w / 2, -h / 2}, {w / 2, h / 2}, {-w / 2, h / 2}, {-w / 2, -h / 2}};
  for (int k = 0; k < 4; ++k) {
    const Vec2 a = corners[k], b = corners[k + 1];
    const int m = static_cast<int>((b - a).norm() / step);
    for (int i = 0; i < m; ++i) {
      Vec2 p = a + (b - a) * (double(i) / m);
      if (jitter > 0.0) p += Vec2(n(rng), n(rng));
      out.push_back(RotateAbout(p, Vec2(0, 0), angle));
    }
  }
  return out;
}

TEST(DominantOrientation, RotatedRoomGivesItsAngleBack) {
  for (double deg : {-44.0, -30.0, -7.5, 0.0, 3.2, 17.0, 29.0, 44.5}) {
    const Orientation o = DominantOrientation(Room(50, 35, DegToRad(deg)));
    ASSERT_TRUE(o.valid);
    const double err = RadToDeg(std::remainder(o.angle_rad - DegToRad(deg), kPi / 2.0));
    EXPECT_NEAR(err, 0.0, 0.1) << deg;
    EXPECT_GT(o.contrast, 2.0) << deg;
  }
}

TEST(DominantOrientation, FoldsIntoTheQuarterTurn) {
  // 60 degrees is -30 modulo 90.
  const Orientation o = DominantOrientation(Room(40, 40, DegToRad(60.0)));
  EXPECT_NEAR(RadToDeg(o.angle_rad), -30.0, 0.1);
  EXPECT_GE(o.angle_rad, -kPi / 4.0);
  EXPECT_LT(o.angle_rad, kPi / 4.0);
}

TEST(DominantOrientation, ThickNoisyWallsStillWithinHalfADegree) {
  const Orientation o = DominantOrientation(Room(60, 40, DegToRad(12.0), 0.25, 0.8, 7));
  EXPECT_NEAR(RadToDeg(o.angle_rad), 12.0, 0.5);
}

TEST(DominantOrientation, CellLatticeDoesNotPullTowardZero) {
  // Cell centres of a wall drawn at 2 degrees: the lattice itself lines up at 0.
  std::vector<Vec2> cells;
  for (int x = 0; x < 80; ++x)
    for (const double y0 : {0.0, 30.0}) {
      const double y = y0 + std::tan(DegToRad(2.0)) * x;
      cells.push_back(Vec2(x + 0.5, std::floor(y) + 0.5));
    }
  for (int y = 0; y < 30; ++y)
    for (const double x0 : {0.0, 80.0}) {
      const double x = x0 - std::tan(DegToRad(2.0)) * y;
      cells.push_back(Vec2(std::floor(x) + 0.5, y + 0.5));
    }
  const Orientation o = DominantOrientation(cells);
  EXPECT_NEAR(RadToDeg(o.angle_rad), 2.0, 0.3);
}

TEST(DominantOrientation, RoundRoomHasLowContrast) {
  std::vector<Vec2> ring;
  for (int i = 0; i < 400; ++i) ring.push_back(Vec2(30 * std::cos(i * 2 * kPi / 400), 30 * std::sin(i * 2 * kPi / 400)));
  const Orientation round = DominantOrientation(ring);
  const Orientation square = DominantOrientation(Room(50, 50, 0.3));
  ASSERT_TRUE(round.valid);
  EXPECT_LT(round.contrast, 1.2);
  EXPECT_GT(square.contrast, 2.0 * round.contrast);
}

TEST(DominantOrientation, TooFewPointsIsNotValid) {
  EXPECT_FALSE(DominantOrientation({}).valid);
  EXPECT_FALSE(DominantOrientation({Vec2(0, 0), Vec2(1, 1)}).valid);
  // All points on one spot: valid, finite.
  const Orientation o = DominantOrientation(std::vector<Vec2>(20, Vec2(3, 3)));
  EXPECT_TRUE(std::isfinite(o.angle_rad));
  EXPECT_TRUE(std::isfinite(o.contrast));
}

}  // namespace
}  // namespace cogmap::vectorize

namespace cogmap::vectorize {
namespace {
// The profile score written as its definition reads: each bin's smoothed
// density summed tap by tap over the taps that fall inside the histogram.
double ProfileByDefinition(const std::vector<Vec2>& points, const Vec2& normal, double sigma) {
  if (points.empty()) return 0.0;
  const int per = 4, pad = 3 * per;
  const double bin = sigma / per;
  double lo = 1e300, hi = -1e300;
  std::vector<double> t;
  for (const Vec2& p : points) {
    t.push_back(p.dot(normal) / bin);
    lo = std::min(lo, t.back());
    hi = std::max(hi, t.back());
  }
  lo -= pad;
  const size_t n = static_cast<size_t>(std::floor(hi - lo)) + 2 * pad + 2;
  std::vector<double> h(n, 0.0);
  for (double v : t) {
    const size_t b = static_cast<size_t>(v - lo);
    const double f = (v - lo) - static_cast<double>(b);
    h[b] += 1.0 - f;
    h[b + 1] += f;
  }
  double s = 0.0;
  const int nn = static_cast<int>(n);
  for (int b = 0; b < nn; ++b) {
    double v = 0.0;
    for (int i = std::max(-pad, -b); i <= std::min(pad, nn - 1 - b); ++i) {
      const double u = static_cast<double>(i) / per;
      v += std::exp(-0.5 * u * u) * h[b + i];
    }
    s += v * v;
  }
  return s;
}

TEST(Orientation, ScoreIsExactlyItsDefinition) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-6.0, 6.0), a(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec2> pts = trial % 2 ? Room(8.0, 5.0, a(rng), 0.1, 0.02, trial) : std::vector<Vec2>{};
    for (int k = 0; k < trial * 7; ++k) pts.push_back(Vec2(u(rng), u(rng)));
    for (double sigma : {0.05, 0.1, 0.4}) {
      const double theta = a(rng);
      const Vec2 n1(std::cos(theta), std::sin(theta)), n2(-n1.y(), n1.x());
      EXPECT_EQ(OrientationScore(pts, theta, sigma),
                ProfileByDefinition(pts, n1, sigma) + ProfileByDefinition(pts, n2, sigma))
          << trial << " " << sigma;
    }
  }
}
}  // namespace
}  // namespace cogmap::vectorize
