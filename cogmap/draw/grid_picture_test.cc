#include "cogmap/draw/grid_picture.h"

#include <gtest/gtest.h>

#include "cogmap/core/pose2.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::draw {
namespace {

using grid::CellClass;
using grid::Grid2D;
using grid::MapLimits;

TEST(RenderCertainty, MhimmColoursWithYUp) {
  Grid2D<float> g(MapLimits(0.1, Vec2(0, 0), 3, 2), 0.0f);
  g.at(0, 0) = -100.0f;  // path
  g.at(1, 0) = 15.0f;    // occupied
  g.at(2, 0) = -3.0f;    // empty
  g.at(0, 1) = 0.0f;     // unknown
  g.at(1, 1) = 7.0f;     // not yet occupied: dark grey
  g.at(2, 1) = -1.5f;    // half way to white
  const io::RgbImage img = RenderCertainty(g);
  ASSERT_EQ(img.width(), 3);
  ASSERT_EQ(img.height(), 2);
  EXPECT_EQ(img.at(0, 1), kRobotPathRgb);  // grid row 0 is the image's bottom row
  EXPECT_EQ(img.at(1, 1), kOccupiedRgb);
  EXPECT_EQ(img.at(2, 1), kEmptyRgb);
  EXPECT_EQ(img.at(0, 0), kUnknownRgb);
  EXPECT_EQ(img.at(1, 0), (io::Rgb{64, 64, 64}));
  EXPECT_EQ(img.at(2, 0).r, 208);  // (160 + 255) / 2 rounded
}

TEST(RenderCertainty, ScaleRepeatsCells) {
  Grid2D<float> g(MapLimits(0.1, Vec2(0, 0), 2, 1), 0.0f);
  g.at(1, 0) = 15.0f;
  GridRenderOptions o;
  o.scale = 3;
  const io::RgbImage img = RenderCertainty(g, o);
  EXPECT_EQ(img.width(), 6);
  EXPECT_EQ(img.height(), 3);
  EXPECT_EQ(img.at(2, 2), kUnknownRgb);
  EXPECT_EQ(img.at(3, 0), kOccupiedRgb);
  EXPECT_EQ(img.at(5, 2), kOccupiedRgb);
}

TEST(RenderProbability, GreyByProbabilityUnknownAndPath) {
  Grid2D<float> p(MapLimits(0.1, Vec2(0, 0), 3, 1), 0.5f);
  Grid2D<CellClass> c(p.limits(), CellClass::kUnknown);
  p.at(1, 0) = 1.0f;
  c.at(1, 0) = CellClass::kOccupied;
  c.at(2, 0) = CellClass::kRobotPath;
  const io::RgbImage img = RenderProbability(p, c);
  EXPECT_EQ(img.at(0, 0), kUnknownRgb);
  EXPECT_EQ(img.at(1, 0), (io::Rgb{0, 0, 0}));
  EXPECT_EQ(img.at(2, 0), kRobotPathRgb);
}

TEST(RenderFusion, MhimmGridShowsPathHitAndBeam) {
  grid::GridBounds b;
  b.fixed = MapLimits(0.1, Vec2(-1, -1), 30, 20);
  auto f = grid::MakeFusion(grid::FusionRule::kMhimm, {b, {}, {}, {}});
  sensors::RangeSensor s;
  f->MarkRobot(Pose2{0.05, 0.05, 0});
  for (int i = 0; i < 3; ++i) f->Insert(Pose2{0.05, 0.05, 0}, s, 1.0);
  const io::RgbImage img = RenderFusion(*f);
  const int row = 20 - 1 - 10;
  EXPECT_EQ(img.at(10, row), kRobotPathRgb);
  EXPECT_EQ(img.at(20, row), kOccupiedRgb);
  EXPECT_EQ(img.at(15, row), kEmptyRgb);
}

TEST(DrawGrid, FitsTheBudgetAndKeepsWallsWhenShrunk) {
  // A 3000 x 10 cell grid (300 m x 1 m) with one occupied column in the middle.
  grid::GridBounds b;
  b.fixed = MapLimits(0.1, Vec2(0, 0), 3000, 10);
  auto f = grid::MakeFusion(grid::FusionRule::kBayes, {b, {}, {}, {}});
  const io::RgbImage cells = RenderFusion(*f);
  EXPECT_EQ(cells.width(), 3000);
  io::RgbImage wall(3000, 10, {255, 255, 255});
  for (int y = 0; y < 10; ++y) wall.at(1501, y) = {0, 0, 0};
  const io::RgbImage small = ShrinkKeepingDarkest(wall, 0.25);
  EXPECT_EQ(small.width(), 750);
  EXPECT_EQ(small.at(375, 1), (io::Rgb{0, 0, 0}));
  EXPECT_EQ(small.at(374, 1), (io::Rgb{255, 255, 255}));
  const Drawing d = DrawGrid(*f);
  EXPECT_LE(d.width(), 2000);
  EXPECT_GE(d.width(), 1990);
  EXPECT_LE(d.height(), 2000);
}

}  // namespace
}  // namespace cogmap::draw
