#include "cogmap/vectorize/vectorize.h"

#include <gtest/gtest.h>

#include "cogmap/vectorize/synthetic_grid.h"

namespace cogmap::vectorize {
namespace {

double NearestVertex(const std::vector<Polyline>& lines, const Vec2& p) {
  double best = 1e300;
  for (const auto& l : lines)
    for (const auto& v : l) best = std::min(best, (v - p).norm());
  return best;
}

double DistanceToWalls(const std::vector<Segment2>& walls, const Vec2& p) {
  double best = 1e300;
  for (const auto& w : walls) best = std::min(best, PointSegmentDistance(p, w.a, w.b));
  return best;
}

TEST(Vectorize, PaperOptions) {
  const auto o = VectorizeOptions::Paper();
  EXPECT_EQ(o.fit.mode, FitMode::kPaper);
  EXPECT_EQ(o.clean.keep, KeepCell::kFace);
  EXPECT_EQ(VectorizeOptions{}.clean.keep, KeepCell::kRunMiddle);
  EXPECT_EQ(o.smooth_half_window, 0);
  EXPECT_EQ(o.clean.max_dist_cells, 30);
  EXPECT_EQ(o.extract.gamma_cells, 4.0);
  EXPECT_EQ(o.vertex_simplify.tau_cells, 2.0);
  EXPECT_EQ(o.douglas_peucker.eta_cells, 1.5);
  EXPECT_EQ(o.fit.min_abs_pearson, 0.9);
}

class SquareRoom : public ::testing::TestWithParam<FitMode> {};

// A 4 m x 3 m room, the path a loop 0.8 m inside: four walls, each within one
// cell (0.1 m) of the truth, in both fit modes.
TEST_P(SquareRoom, FourWallsWithinOneCell) {
  const auto walls = RectangleWalls(Vec2(1, 1), Vec2(5, 4));
  const Polyline path = {Vec2(1.8, 1.8), Vec2(4.2, 1.8), Vec2(4.2, 3.2), Vec2(1.8, 3.2), Vec2(1.8, 1.8)};
  const auto grid = MakeSyntheticGrid(walls, path);
  const auto o = GetParam() == FitMode::kPaper ? VectorizeOptions::Paper() : VectorizeOptions{};
  const auto r = Vectorize(grid, o);
  ASSERT_EQ(r.polylines.size(), 1u);
  const auto& l = r.polylines[0];
  EXPECT_EQ(l.size(), 5u);
  EXPECT_EQ(l.front(), l.back());
  for (const auto& v : l) EXPECT_LE(DistanceToWalls(walls, v), 0.1) << v.transpose();
  // Default mode closes corners at the lines' intersection (within a cell: the
  // faces lie half a cell inside and the corner cell tilts both fits a
  // little); paper mode averages the two projections, which rounds a corner.
  const double corner_tol = GetParam() == FitMode::kDefault ? 0.1 : 0.2;
  for (const Vec2& c : {Vec2(1, 1), Vec2(5, 1), Vec2(5, 4), Vec2(1, 4)})
    EXPECT_LE(NearestVertex(r.polylines, c), corner_tol) << c.transpose();
  for (const auto& seg : ToSegments(r.polylines)) {
    const Vec2 d = seg.b - seg.a;
    EXPECT_LE(std::min(std::abs(d.x()), std::abs(d.y())), 0.1 + 1e-9) << "not axis-aligned";
  }
  EXPECT_EQ(r.vertex_count, 5);
  EXPECT_EQ(r.bytes.grid, grid.limits().cell_count());
  EXPECT_EQ(r.bytes.vertices, 4 * r.extract_stats.points);
  EXPECT_EQ(r.bytes.polylines, static_cast<int64_t>(EncodePolylines(r.polylines).size()));
  EXPECT_LT(r.bytes.polylines, r.bytes.vertices / 10);
}

INSTANTIATE_TEST_SUITE_P(Modes, SquareRoom, ::testing::Values(FitMode::kPaper, FitMode::kDefault));

TEST(Vectorize, LShapedRoomKeepsItsCorner) {
  const std::vector<Vec2> poly = {Vec2(0, 0), Vec2(6, 0), Vec2(6, 3), Vec2(3, 3), Vec2(3, 6), Vec2(0, 6)};
  std::vector<Segment2> walls;
  for (size_t i = 0; i < poly.size(); ++i) walls.push_back({poly[i], poly[(i + 1) % poly.size()]});
  const Polyline path = {Vec2(1, 5), Vec2(1, 1), Vec2(5, 1), Vec2(5, 2), Vec2(2, 2), Vec2(2, 5)};
  const auto r = Vectorize(MakeSyntheticGrid(walls, path));
  ASSERT_FALSE(r.polylines.empty());
  EXPECT_LE(NearestVertex(r.polylines, Vec2(3, 3)), 0.15);
  for (const auto& c : poly) EXPECT_LE(NearestVertex(r.polylines, c), 0.15) << c.transpose();
}

TEST(Vectorize, ThickNoisyWallsStillGiveFourWalls) {
  const auto walls = RectangleWalls(Vec2(1, 1), Vec2(9, 7));
  const Polyline path = {Vec2(2, 2), Vec2(8, 2), Vec2(8, 6), Vec2(2, 6), Vec2(2, 2)};
  SyntheticGridOptions g;
  g.wall_half_width_m = 0.3;  // walls 6 cells thick
  g.see_m = 3.0;
  const auto r = Vectorize(MakeSyntheticGrid(walls, path, g));
  ASSERT_EQ(r.polylines.size(), 1u);
  EXPECT_EQ(r.polylines[0].size(), 5u);
  for (const auto& v : r.polylines[0]) EXPECT_LE(DistanceToWalls(walls, v), 0.3 + 0.1);
}

// A wall whose cells alternate between two rows: smoothing puts the fitted
// wall on their mean row.
TEST(Vectorize, SmoothingDampsAZigZagBand) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 60, 30), 0.0f);
  for (int x = 5; x < 55; ++x) g.at(x, 20 + (x / 2) % 2) = 15.0f;
  for (int x = 5; x < 55; ++x) g.at(x, 5) = -100.0f;
  VectorizeOptions o;
  o.clean.keep = KeepCell::kFace;
  o.smooth_half_window = 2;
  const auto r = Vectorize(g, o);
  ASSERT_EQ(r.polylines.size(), 1u);
  ASSERT_EQ(r.polylines[0].size(), 2u);
  for (const auto& v : r.polylines[0]) EXPECT_NEAR(v.y(), 2.1, 0.03);
}

TEST(Vectorize, EmptyGridGivesNoWalls) {
  const auto r = Vectorize(grid::Grid2D<float>());
  EXPECT_TRUE(r.polylines.empty());
  EXPECT_EQ(r.bytes.grid, 0);
  EXPECT_EQ(r.bytes.vertices, 0);
}

TEST(Vectorize, AllUnknownGridGivesNoWalls) {
  const grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 50, 40), 0.0f);
  const auto r = Vectorize(g);
  EXPECT_TRUE(r.polylines.empty());
  EXPECT_EQ(r.bytes.grid, 2000);
}

// No robot path: cleaning has nothing to see the walls from, so nothing is a
// wall (documented in Vectorize).
TEST(Vectorize, NoRobotPathGivesNoWalls) {
  const auto grid = MakeSyntheticGrid(RectangleWalls(Vec2(1, 1), Vec2(5, 4)), {});
  const auto r = Vectorize(grid);
  EXPECT_GT(std::count_if(grid.cells().begin(), grid.cells().end(), [](float v) { return v > 7; }), 100);
  EXPECT_TRUE(r.polylines.empty());
  EXPECT_EQ(r.clean_stats.kept, 0);
}

TEST(Vectorize, SingleOccupiedCellIsNotAWall) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 20, 20), 0.0f);
  g.at(5, 5) = 15.0f;
  g.at(10, 10) = -100.0f;
  const auto r = Vectorize(g);
  EXPECT_EQ(r.extract_stats.points, 1);
  EXPECT_EQ(r.dropped_chains, 1);
  EXPECT_TRUE(r.polylines.empty());
}

TEST(Vectorize, OneCellGapsStayOneWall) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 60, 20), 0.0f);
  for (int x = 5; x < 55; ++x)
    if (x % 2 == 0) g.at(x, 15) = 15.0f;
  for (int x = 5; x < 55; ++x) g.at(x, 5) = -100.0f;
  const auto r = Vectorize(g);
  ASSERT_EQ(r.polylines.size(), 1u);
  EXPECT_EQ(r.polylines[0].size(), 2u);
  EXPECT_NEAR(r.polylines[0][0].y(), 1.55, 1e-9);
  EXPECT_NEAR(r.polylines[0][1].y(), 1.55, 1e-9);
}

TEST(Vectorize, HorizontalAndVerticalWallsInPaperMode) {
  grid::Grid2D<float> g(grid::MapLimits(0.1, Vec2(0, 0), 40, 40), 0.0f);
  for (int i = 5; i < 35; ++i) g.at(i, 30) = 15.0f;  // horizontal
  for (int i = 5; i < 25; ++i) g.at(35, i) = 15.0f;  // vertical, 10+ cells apart
  for (int i = 5; i < 30; ++i) g.at(i, 10) = -100.0f;
  const auto r = Vectorize(g, VectorizeOptions::Paper());
  ASSERT_EQ(r.polylines.size(), 2u);
  EXPECT_EQ(r.fit_stats.rejected, 0);
  EXPECT_EQ(r.fit_stats.fitted, 2);
}

}  // namespace
}  // namespace cogmap::vectorize
