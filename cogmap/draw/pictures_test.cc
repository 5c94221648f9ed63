// The floor plan, world, vectorize-stage and wall pictures: sizes within the
// budget and pixels where the geometry puts them.
#include <gtest/gtest.h>

#include "cogmap/draw/stages_picture.h"
#include "cogmap/draw/svg_test_util.h"
#include "cogmap/draw/world_picture.h"
#include "cogmap/vectorize/synthetic_grid.h"

namespace cogmap::draw {
namespace {

constexpr io::Rgb kBlackRgb{0, 0, 0};

// Two rooms side by side, 5 x 4 m each, a door in the shared wall at y 1..2.
plan::Plan TwoRoomPlan() {
  plan::Plan p;
  auto wall = [&](std::vector<Vec2> pts) {
    plan::Wall w;
    w.points = std::move(pts);
    p.walls.push_back(w);
  };
  wall({Vec2(0, 0), Vec2(10, 0), Vec2(10, 4), Vec2(0, 4), Vec2(0, 0)});
  wall({Vec2(5, 0), Vec2(5, 1)});
  wall({Vec2(5, 2), Vec2(5, 4)});
  for (int i = 0; i < 2; ++i) {
    plan::Room r;
    r.id = i;
    r.name = i == 0 ? "Room 1" : "Corridor 1";
    r.corridor = i == 1;
    r.polygon = {Vec2(5 * i, 0), Vec2(5 * i + 5, 0), Vec2(5 * i + 5, 4), Vec2(5 * i, 4)};
    r.area_m2 = 20;
    r.label = Vec2(5 * i + 2.5, 3);
    r.doors = {0};
    p.rooms.push_back(r);
  }
  plan::Door door;
  door.id = 0;
  door.a = Vec2(5, 1);
  door.b = Vec2(5, 2);
  door.room_a = 0;
  door.room_b = 1;
  p.doors = {door};
  p.edges = {{0, 1, 0}};
  p.home = Pose2{1, 1, 0};
  p.min = Vec2(0, 0);
  p.max = Vec2(10, 4);
  return p;
}

TEST(DrawPlan, WallsRoomsDoorsAndLabels) {
  PlanPictureOptions o;
  o.room_graph = true;
  const MapPicture pic = DrawPlan(TwoRoomPlan(), o);
  EXPECT_LE(std::max(pic.drawing.width(), pic.drawing.height()), 2000);
  EXPECT_EQ(pic.labels_placed, 2);
  const io::RgbImage img = test::DecodePng(pic.drawing.Encode(Format::kPng), "plan.png");
  for (const Vec2& w : {Vec2(2, 0), Vec2(8, 4), Vec2(10, 2), Vec2(5, 0.5), Vec2(5, 3)}) {
    const Vec2 px = pic.Px(w);
    EXPECT_TRUE(test::ColourNear(img, px.x(), px.y(), kBlackRgb, 1, 30)) << w.transpose();
  }
  const Vec2 door = pic.Px(Vec2(5, 1.3));
  EXPECT_TRUE(test::ColourNear(img, door.x(), door.y(), {255, 150, 0}, 1, 30));
  const Vec2 in_room = pic.Px(Vec2(1, 2.5)), in_corridor = pic.Px(Vec2(9, 0.5));
  EXPECT_EQ(img.at(static_cast<int>(in_room.x()), static_cast<int>(in_room.y())), (io::Rgb{235, 242, 255}));
  EXPECT_EQ(img.at(static_cast<int>(in_corridor.x()), static_cast<int>(in_corridor.y())), (io::Rgb{238, 238, 238}));
}

TEST(DrawPlan, SameDrawingToSvgAndPdf) {
  const MapPicture pic = DrawPlan(TwoRoomPlan());
  const auto paths = test::ParseSvgPaths(pic.drawing.Encode(Format::kSvg));
  int outer_wall = 0;
  for (const auto& p : paths)
    if (p.stroked && p.r == 0 && p.g == 0 && p.b == 0 && p.points.size() == 5) {
      ++outer_wall;
      EXPECT_NEAR(p.points[1].x(), pic.Px(Vec2(10, 0)).x(), 0.01);
      EXPECT_NEAR(p.points[2].y(), pic.Px(Vec2(10, 4)).y(), 0.01);
    }
  EXPECT_EQ(outer_wall, 1);
  EXPECT_EQ(pic.drawing.Encode(Format::kPdf).rfind("%PDF-", 0), 0u);
}

TEST(DrawPlan, EmptyPlanStillDraws) {
  const MapPicture pic = DrawPlan(plan::Plan{});
  EXPECT_GT(pic.drawing.width(), 0);
  EXPECT_LE(pic.drawing.width(), 2000);
}

TEST(DrawWorld, WallsAndPathsWhereTheyAre) {
  FloorPlan w;
  w.walls = {{Vec2(0, 0), Vec2(20, 0)}, {Vec2(20, 0), Vec2(20, 10)}};
  w.rooms = {{"hall", Vec2(0, 0), Vec2(20, 10)}};
  w.min = Vec2(0, 0);
  w.max = Vec2(20, 10);
  const MapPicture pic = DrawWorld(w, {Vec2(2, 5), Vec2(18, 5)}, {Vec2(2, 6), Vec2(18, 7)});
  EXPECT_LE(pic.drawing.width(), 2000);
  EXPECT_GE(pic.drawing.width(), 1990);
  const io::RgbImage img = pic.drawing.Rasterize();
  const Vec2 wall = pic.Px(Vec2(10, 0)), truth = pic.Px(Vec2(6, 5)), odo = pic.Px(Vec2(10, 6.5));
  EXPECT_TRUE(test::ColourNear(img, wall.x(), wall.y(), kBlackRgb, 1, 30));
  EXPECT_TRUE(test::ColourNear(img, truth.x(), truth.y(), {0, 170, 0}, 1, 30));
  EXPECT_TRUE(test::ColourNear(img, odo.x(), odo.y(), {230, 0, 0}, 1, 30));
}

TEST(DrawStages, FivePanelsWithinTheBudget) {
  const auto walls = vectorize::RectangleWalls(Vec2(1, 1), Vec2(5, 4));
  const Polyline path = {Vec2(1.8, 1.8), Vec2(4.2, 1.8), Vec2(4.2, 3.2)};
  const auto grid = vectorize::MakeSyntheticGrid(walls, path);
  const auto r = vectorize::Vectorize(grid);
  const StagesPicture pic = DrawStages(grid, r);
  const Drawing& d = pic.drawing;
  EXPECT_LE(d.width(), 2000);
  EXPECT_LE(d.height(), 2000);
  EXPECT_GE(d.width(), 1990);
  // One scale for every panel, with its bar in the band below them: the
  // bar's pixels are its metres at that scale.
  EXPECT_GT(pic.px_per_m, 0.0);
  EXPECT_GT(pic.scale_bar.start_px.y(), pic.band_top_px);
  EXPECT_LT(pic.scale_bar.start_px.y(), d.height());
  EXPECT_NEAR(pic.scale_bar.end_px.x() - pic.scale_bar.start_px.x(), pic.scale_bar.length_m * pic.px_per_m, 1e-9);
  const io::RgbImage img = d.Rasterize();
  // The fitted panel (the fifth) has black wall pixels; the raw panel too.
  int black_fifth = 0, black_first = 0;
  const int panel = static_cast<int>((d.width() - 60) / 5);
  for (int y = 70; y < static_cast<int>(pic.band_top_px); ++y)
    for (int x = 0; x < img.width(); ++x)
      if (img.at(x, y) == kBlackRgb) (x > img.width() - panel - 10 ? black_fifth : black_first) += x < panel + 10 || x > img.width() - panel - 10;
  EXPECT_GT(black_fifth, 100);
  EXPECT_GT(black_first, 100);
  // An empty result draws blank panels.
  EXPECT_GT(DrawStages(grid::Grid2D<float>(), vectorize::VectorizeResult{}).drawing.width(), 0);
}

TEST(DrawWalls, WallsOverTruth) {
  const std::vector<Segment2> truth = {{Vec2(0, 0), Vec2(6, 0)}};
  const std::vector<Polyline> walls = {{Vec2(0, 0.02), Vec2(6, 0.02)}, {Vec2(0, 5), Vec2(6, 5)}};
  const MapPicture pic = DrawWalls(walls, truth, {});
  const io::RgbImage img = pic.drawing.Rasterize();
  const Vec2 top = pic.Px(Vec2(3, 5));
  EXPECT_TRUE(test::ColourNear(img, top.x(), top.y(), kBlackRgb, 1, 30));
  const Vec2 under = pic.Px(Vec2(3, 0)) + Vec2(0, 2.5);  // the truth's band below the wall
  EXPECT_TRUE(test::ColourNear(img, under.x(), under.y(), {150, 190, 255}, 1, 30));
}

}  // namespace
}  // namespace cogmap::draw
