#include "cogmap/vectorize/line_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace cogmap::vectorize {
namespace {

LineFitOptions Paper() {
  LineFitOptions o;
  o.mode = FitMode::kPaper;
  return o;
}

TEST(LineFit, PaperDefaults) {
  const LineFitOptions o;
  EXPECT_EQ(o.min_abs_pearson, 0.9);  // §3.1.8
  EXPECT_EQ(o.mode, FitMode::kDefault);
}

std::vector<Vec2> PointRun(const Vec2& a, const Vec2& b, int n) {
  std::vector<Vec2> p;
  for (int i = 0; i < n; ++i) p.push_back(a + (b - a) * (static_cast<double>(i) / (n - 1)));
  return p;
}

TEST(LineFit, ExactlyHorizontalWallFitsInPaperMode) {
  const auto l = FitLine(PointRun(Vec2(0, 3), Vec2(10, 3), 11), Paper());
  EXPECT_TRUE(l.accepted);
  EXPECT_EQ(l.quality, 1.0);
  EXPECT_NEAR(std::abs(l.direction.x()), 1.0, 1e-12);
  EXPECT_NEAR(l.point.y(), 3.0, 1e-12);
}

TEST(LineFit, ExactlyVerticalWallFitsInPaperMode) {
  const auto l = FitLine(PointRun(Vec2(4, 0), Vec2(4, 10), 11), Paper());
  EXPECT_TRUE(l.accepted);
  EXPECT_NEAR(std::abs(l.direction.y()), 1.0, 1e-12);
  EXPECT_NEAR(l.point.x(), 4.0, 1e-12);
}

TEST(LineFit, ExactWallsFitInDefaultMode) {
  for (const std::vector<Vec2>& pts : std::vector<std::vector<Vec2>>{PointRun(Vec2(0, 3), Vec2(10, 3), 11), PointRun(Vec2(4, 0), Vec2(4, 10), 11)}) {
    const auto l = FitLine(pts);
    EXPECT_TRUE(l.accepted);
    EXPECT_NEAR(l.quality, 0.0, 1e-12);
  }
}

// The Pearson pitfall (SPEC 3.5): a noisy horizontal wall has |rho| near 0,
// so the paper's gate rejects it; the rotation-invariant gate accepts it.
TEST(LineFit, NoisyHorizontalWallRejectedByPearsonOnly) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 20; ++i) pts.push_back(Vec2(i, 5.0 + ((i * 7) % 3 - 1) * 0.5));
  EXPECT_FALSE(FitLine(pts, Paper()).accepted);
  EXPECT_TRUE(FitLine(pts).accepted);
}

TEST(LineFit, DefaultGateIsRotationInvariant) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.3);
  std::vector<Vec2> pts;
  for (int i = 0; i <= 30; ++i) pts.push_back(Vec2(i, n(rng)));
  const double q0 = FitLine(pts).quality;
  for (double deg : {17.0, 45.0, 90.0, 133.0}) {
    const double c = std::cos(deg * M_PI / 180), s = std::sin(deg * M_PI / 180);
    std::vector<Vec2> r;
    for (const auto& p : pts) r.push_back(Vec2(c * p.x() - s * p.y(), s * p.x() + c * p.y()));
    EXPECT_NEAR(FitLine(r).quality, q0, 1e-9) << deg;
  }
}

TEST(LineFit, AllPointsEqualIsNotAccepted) {
  EXPECT_FALSE(FitLine({Vec2(1, 1), Vec2(1, 1), Vec2(1, 1)}).accepted);
  EXPECT_FALSE(FitLine({Vec2(1, 1), Vec2(1, 1), Vec2(1, 1)}, Paper()).accepted);
}

// An L of noisy points: the corner vertex lands on the intersection of the two
// fitted lines in default mode.
TEST(FitEdges, CornerClosesAtIntersection) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 10; ++i) pts.push_back(Vec2(i, (i % 2) * 0.4));      // y ~ 0.2
  for (int j = 1; j <= 10; ++j) pts.push_back(Vec2(10 + (j % 2) * 0.4, j));  // x ~ 10.2
  LineFitStats st;
  const auto out = FitEdges(pts, {0, 10, 20}, {}, &st);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(st.fitted, 2);
  EXPECT_EQ(st.corners_joined, 1);
  EXPECT_NEAR(out[1].x(), 10.2, 0.05);
  EXPECT_NEAR(out[1].y(), 0.2, 0.05);
  EXPECT_NEAR(out[0].y(), out[1].y(), 0.05);  // bottom edge level
  EXPECT_NEAR(out[2].x(), out[1].x(), 0.05);  // right edge upright
}

// Two long walls joined by a short diagonal (a rounded corner): the chamfer
// goes and the walls meet at their corner.
TEST(FitEdges, ChamferBecomesACorner) {
  std::vector<Vec2> pts;
  for (int i = 0; i <= 20; ++i) pts.push_back(Vec2(i, 0));       // 0..20
  for (int i = 1; i <= 3; ++i) pts.push_back(Vec2(20 + i, i));   // 21..23 diagonal
  for (int j = 4; j <= 24; ++j) pts.push_back(Vec2(23, j));      // 24..44
  LineFitStats st;
  const auto out = FitEdges(pts, {0, 20, 23, 44}, {}, &st);
  EXPECT_EQ(st.chamfers_removed, 1);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_NEAR(out[1].x(), 23.0, 1e-6);
  EXPECT_NEAR(out[1].y(), 0.0, 1e-6);
  LineFitOptions off;
  off.max_chamfer_cells = 0.0;
  EXPECT_EQ(FitEdges(pts, {0, 20, 23, 44}, off).size(), 4u);
}

TEST(FitEdges, RejectedEdgeKeepsItsVertices) {
  // A semicircle arc: far from straight, both gates reject it.
  std::vector<Vec2> pts;
  for (int i = 0; i <= 20; ++i) pts.push_back(Vec2(10 * std::cos(M_PI * i / 20), 10 * std::sin(M_PI * i / 20)));
  LineFitStats st;
  const auto out = FitEdges(pts, {0, 20}, {}, &st);
  EXPECT_EQ(st.rejected, 1);
  EXPECT_EQ(out[0], pts[0]);
  EXPECT_EQ(out[1], pts[20]);
}

}  // namespace
}  // namespace cogmap::vectorize
