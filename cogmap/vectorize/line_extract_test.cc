#include "cogmap/vectorize/line_extract.h"

#include <gtest/gtest.h>

#include <cmath>

#include "cogmap/core/angles.h"
#include "cogmap/vectorize/synthetic_grid.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::vectorize {
namespace {

// Distance (cells) from p to the nearest of 'targets'.
double Nearest(const Vec2& p, const std::vector<Vec2>& targets) {
  double best = 1e300;
  for (const auto& t : targets) best = std::min(best, (p - t).norm());
  return best;
}

LineExtractResult Lines(const grid::Grid2D<float>& g, const LineExtractOptions& o = {}) {
  CleanOptions c;
  c.keep = KeepCell::kRunMiddle;
  return ExtractWallLines(CleanMap(g, c), g, o);
}

// A square room of side 3.9 m whose corners are rounded (arcs of 0.6 m, as a
// sonar grid draws them), walked round inside.
TEST(ExtractWallLines, RoundedSquareRoomGivesFourWallsMeetingAtTheCorners) {
  const double lo = 1.05, hi = 4.95, r = 0.6;
  std::vector<Segment2> walls = {{{lo + r, lo}, {hi - r, lo}},
                                 {{hi, lo + r}, {hi, hi - r}},
                                 {{hi - r, hi}, {lo + r, hi}},
                                 {{lo, hi - r}, {lo, lo + r}}};
  const Vec2 centres[4] = {{lo + r, lo + r}, {hi - r, lo + r}, {hi - r, hi - r}, {lo + r, hi - r}};
  for (int c = 0; c < 4; ++c)  // each arc as 12 chords
    for (int k = 0; k < 12; ++k) {
      const double a0 = kPi + c * kPi / 2 + k * kPi / 24, a1 = a0 + kPi / 24;
      walls.push_back({centres[c] + r * Vec2(std::cos(a0), std::sin(a0)), centres[c] + r * Vec2(std::cos(a1), std::sin(a1))});
    }
  const Polyline path = {{2, 2}, {4, 2}, {4, 4}, {2, 4}, {2, 2}};
  const auto grid = MakeSyntheticGrid(walls, path);
  const auto result = Lines(grid);
  ASSERT_EQ(result.walls.size(), 1u);
  const auto& ring = result.walls[0];
  ASSERT_EQ(ring.size(), 5u);  // four corners, the first repeated
  EXPECT_EQ(ring.front(), ring.back());
  const auto& lim = grid.limits();
  std::vector<Vec2> corners;
  for (const Vec2& p : {Vec2(lo, lo), Vec2(hi, lo), Vec2(hi, hi), Vec2(lo, hi)}) corners.push_back(lim.ToCellCoords(p));
  for (size_t i = 0; i + 1 < ring.size(); ++i) EXPECT_LE(Nearest(ring[i], corners), 1.0) << i;
  EXPECT_EQ(result.stats.corners_joined, 4);
}

// One wall with a 1 m doorway, seen from a path along it.
TEST(ExtractWallLines, DoorGapGivesTwoCollinearSegments) {
  const std::vector<Segment2> walls = {{{1.05, 1.05}, {3.05, 1.05}}, {{4.05, 1.05}, {7.05, 1.05}}};
  const Polyline path = {{1.0, 2.5}, {7.0, 2.5}};
  const auto grid = MakeSyntheticGrid(walls, path);
  const auto result = Lines(grid);
  ASSERT_EQ(result.walls.size(), 2u);
  const auto& lim = grid.limits();
  std::vector<Vec2> ends;
  for (const auto& w : walls) ends.push_back(lim.ToCellCoords(w.a)), ends.push_back(lim.ToCellCoords(w.b));
  const double y = lim.ToCellCoords(Vec2(0, 1.05)).y();
  for (const auto& w : result.walls) {
    ASSERT_EQ(w.size(), 2u);
    for (const auto& p : w) {
      EXPECT_NEAR(p.y(), y, 0.05);
      EXPECT_LE(Nearest(p, ends), 1.0);
    }
  }
  // The gap lies between them.
  const double a_max = std::max(result.walls[0][0].x(), result.walls[0][1].x());
  const double b_min = std::min(result.walls[1][0].x(), result.walls[1][1].x());
  const double gap = std::abs(b_min - a_max) > 5 ? std::abs(b_min - a_max)
                                                   : std::abs(std::min(result.walls[0][0].x(), result.walls[0][1].x()) -
                                                              std::max(result.walls[1][0].x(), result.walls[1][1].x()));
  EXPECT_NEAR(gap, 10.0, 1.0);
}

// A wall at 36.87 degrees stays one straight diagonal.
TEST(ExtractWallLines, DiagonalWallStaysDiagonal) {
  SyntheticGridOptions so;
  so.wall_half_width_m = 0.071;  // a connected band of cells along the diagonal
  const std::vector<Segment2> walls = {{{1.0, 1.0}, {5.0, 4.0}}};
  const Polyline path = {{1.5, 3.0}, {3.5, 4.5}};
  const auto grid = MakeSyntheticGrid(walls, path, so);
  const auto result = Lines(grid);
  ASSERT_EQ(result.walls.size(), 1u);
  ASSERT_EQ(result.walls[0].size(), 2u);
  const Vec2 d = result.walls[0][1] - result.walls[0][0];
  double deg = RadToDeg(std::atan2(d.y(), d.x()));
  if (deg < 0) deg += 180.0;
  EXPECT_NEAR(deg, RadToDeg(std::atan2(3.0, 4.0)), 1.0);
  const auto& lim = grid.limits();
  for (const auto& p : result.walls[0]) EXPECT_LE(PointLineDistance(p, lim.ToCellCoords(walls[0].a), lim.ToCellCoords(walls[0].b)), 0.5);
}

// Two walls whose ends stop 9.5 cells short of their crossing, the robot
// 21.2 cells from it: the blur radius 2 + tan(half-width) x 21.2 reaches the
// ends for a 25-degree half-width (11.9 cells), not for 15 degrees (7.7) nor
// for a laser (2.2).
grid::Grid2D<float> OpenCorner() {
  // Cells drawn directly: walls y = 10.5 (cells x 20 .. 60, ends 20.0 and
  // 61.0) and x = 10.5 (likewise); the crossing at (10.5, 10.5).
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 80, 80), 0.0f);
  for (int i = 20; i <= 60; ++i) g.at(i, 10) = 15.0f, g.at(10, i) = 15.0f;
  g.at(25, 25) = -100.0f;  // one path cell, 21.2 cells from the crossing
  return g;
}

TEST(ExtractWallLines, BlurRadiusFromBeamDecidesTheCorner) {
  const auto g = OpenCorner();
  LineExtractOptions o;
  o.beam_half_width_rad = DegToRad(0.5);  // a laser: radius 2.2 cells < 9.5
  auto laser = ExtractWallLines(g, g, o);
  EXPECT_EQ(laser.walls.size(), 2u);
  EXPECT_EQ(laser.stats.corners_joined, 0);
  o.beam_half_width_rad = DegToRad(25.0);  // radius 11.9 cells > 9.5
  auto sonar = ExtractWallLines(g, g, o);
  ASSERT_EQ(sonar.walls.size(), 1u);
  ASSERT_EQ(sonar.walls[0].size(), 3u);
  EXPECT_NEAR(sonar.walls[0][1].x(), 10.5, 1e-6);
  EXPECT_NEAR(sonar.walls[0][1].y(), 10.5, 1e-6);
  EXPECT_EQ(sonar.stats.corners_joined, 1);
  o.beam_half_width_rad = DegToRad(15.0);  // radius 7.7 cells < 9.5
  EXPECT_EQ(ExtractWallLines(g, g, o).stats.corners_joined, 0);
}

// A wall band the robot drove through (a doorway the sonar blur closed) is
// cut where the robot's body went: clearance 0.26 m less half a cell = 2.1
// cells each side of the path.
TEST(ExtractWallLines, WallIsCutWhereTheRobotDrove) {
  const std::vector<Segment2> walls = {{{1.05, 1.05}, {7.05, 1.05}}};
  const Polyline path = {{1.05, 2.55}, {7.05, 2.55}, {4.05, 2.55}, {4.05, 0.05}};
  const auto grid = MakeSyntheticGrid(walls, path);
  LineExtractOptions o;
  EXPECT_EQ(Lines(grid, o).walls.size(), 1u);  // off: one wall through the path
  o.path_clearance_m = 0.26;
  const auto result = Lines(grid, o);
  ASSERT_EQ(result.walls.size(), 2u);
  EXPECT_EQ(result.stats.path_cuts, 1);
  const double path_x = grid.limits().ToCellCoords(Vec2(4.05, 0)).x();
  for (const auto& w : result.walls) {
    ASSERT_EQ(w.size(), 2u);
    const double inner = std::min(std::abs(w[0].x() - path_x), std::abs(w[1].x() - path_x));
    EXPECT_GE(inner, 2.1);
    EXPECT_LE(inner, 3.6);  // one sampling step (<= 0.5 cell) and the step back
  }
}

// A short segment that meets no other wall is an echo.
TEST(ExtractWallLines, IsolatedShortSegmentIsDropped) {
  const std::vector<Segment2> walls = {{{1.05, 1.05}, {1.45, 1.05}}};  // 0.5 m
  const Polyline path = {{1.0, 2.0}, {1.5, 2.0}};
  const auto grid = MakeSyntheticGrid(walls, path);
  LineExtractOptions o;
  o.min_isolated_m = 0.0;
  EXPECT_EQ(Lines(grid, o).walls.size(), 1u);
  o.min_isolated_m = 0.6;
  const auto result = Lines(grid, o);
  EXPECT_TRUE(result.walls.empty());
  EXPECT_EQ(result.stats.isolated_removed, 1);
}

// Every occupied cell as evidence: a band five cells thick gives its centre line.
TEST(ExtractWallLines, ThickBandGivesItsCentreLine) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 60, 30), 0.0f);
  for (int x = 5; x < 55; ++x)
    for (int y = 8; y <= 12; ++y) g.at(x, y) = 15.0f;
  for (int x = 5; x < 55; ++x) g.at(x, 25) = -100.0f;
  LineExtractOptions o;
  o.all_occupied = true;
  const auto result = ExtractWallLines(g, g, o);
  ASSERT_EQ(result.walls.size(), 1u);
  for (const auto& p : result.walls[0]) EXPECT_NEAR(p.y(), 10.5, 1e-9);
  EXPECT_NEAR(std::min(result.walls[0][0].x(), result.walls[0][1].x()), 5.0, 1e-9);
  EXPECT_NEAR(std::max(result.walls[0][0].x(), result.walls[0][1].x()), 55.0, 1e-9);
}

TEST(ExtractWallLines, EmptyGridGivesNoWalls) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 20, 20), 0.0f);
  EXPECT_TRUE(ExtractWallLines(g, g).walls.empty());
  grid::Grid2D<float> none;
  EXPECT_TRUE(ExtractWallLines(none, none).walls.empty());
}

TEST(Vectorize, WallLinesOffInPaperMode) { EXPECT_FALSE(VectorizeOptions::Paper().wall_lines); }

}  // namespace
}  // namespace cogmap::vectorize
