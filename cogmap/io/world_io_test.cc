#include "cogmap/io/world_io.h"

#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"

namespace cogmap::io {
namespace {

const std::string kShared = COGMAP_SHARED_DIR;

TEST(WorldIo, ReadsNineRooms) {
  const auto r = ReadAriaMap(kShared + "/worlds/nine_rooms.map");
  const FloorPlan& p = r.plan;
  EXPECT_EQ(p.walls.size(), 16u);
  EXPECT_EQ(p.rooms.size(), 9u);
  EXPECT_EQ(p.doorways.size(), 8u);
  EXPECT_EQ(p.route.size(), 66u);
  ASSERT_TRUE(p.home.has_value());
  EXPECT_DOUBLE_EQ(p.home->x, 1.2);
  EXPECT_NEAR(p.home->theta, -kPi / 2, 1e-12);
  EXPECT_EQ(p.route.front().name, "wp01");
  EXPECT_EQ(p.route.back().name, "wp66");
  EXPECT_DOUBLE_EQ(p.max.x(), 15.0);
  EXPECT_EQ(p.rooms[0].name, "room1");
  EXPECT_DOUBLE_EQ(p.rooms[0].max.y(), 4.0);
  EXPECT_DOUBLE_EQ(p.doorways[6].line.a.x(), 12.0);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(WorldIo, ReadsAriaOfficeMap) {
  const auto r = ReadAriaMap(kShared + "/worlds/aria/office.map");
  EXPECT_EQ(r.plan.walls.size(), 101u);
  EXPECT_TRUE(r.plan.home.has_value());
}

TEST(WorldIo, RouteSortedByNumber) {
  const auto r = ParseAriaMap(
      "2D-Map\n"
      "Cairn: GoalWithHeading 3000 0 0 \"\" ICON \"wp10\"\n"
      "Cairn: GoalWithHeading 1000 0 90 \"\" ICON \"wp2\"\n"
      "LINES\n0 0 1000 0\nDATA\n",
      "t.map");
  ASSERT_EQ(r.plan.route.size(), 2u);
  EXPECT_EQ(r.plan.route[0].name, "wp2");
  EXPECT_NEAR(r.plan.route[0].pose.theta, kPi / 2, 1e-12);
}

TEST(WorldIo, UnknownCairnAndDataPointsAreWarningsNamingThem) {
  const auto r = ParseAriaMap(
      "2D-Map\nMinPos: 0 0\nCairn: ForbiddenLine 0 0 0 \"\" ICON \"nogo\" 0 0 100 100\n"
      "Cairn: Goal 0 0 0 \"\" ICON \"kitchen\"\nLINES\n0 0 1000 0\nDATA\n5 5\n6 6\n",
      "t.map");
  ASSERT_EQ(r.warnings.size(), 3u);
  EXPECT_NE(r.warnings[0].find("t.map:3"), std::string::npos);
  EXPECT_NE(r.warnings[0].find("nogo"), std::string::npos);
  EXPECT_NE(r.warnings[1].find("kitchen"), std::string::npos);
  EXPECT_NE(r.warnings[2].find("2 DATA points"), std::string::npos);
}

TEST(WorldIo, MalformedLineNamesFileAndLine) {
  try {
    ParseAriaMap("2D-Map\nLINES\n0 0 1000 0\n0 0 10x 5\n", "bad.map");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.map:4"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseAriaMap("2D-Map\nLINES\n0 0 1000\n", "bad.map"), InputError);
  EXPECT_THROW(ParseAriaMap("hello\n", "bad.map"), InputError);
  EXPECT_THROW(ParseAriaMap("2D-Map\nCairn: Room 0 0 0 \"\" ICON \"r\" 1 2\n", "bad.map"), InputError);
  EXPECT_THROW(ReadAriaMap("/nonexistent/x.map"), InputError);
}

TEST(WorldIo, CoordinatesBeyondAHundredKilometresAreRefused) {
  // Grids and pictures are sized from the extent: 1e15 mm must not reach them.
  const std::string text = "2D-Map\nLineMinPos: 0 0\nLineMaxPos: 1000000000000000 1000\nLINES\n0 0 1000 0\n";
  try {
    ParseAriaMap(text, "far.map");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "far.map:3: LineMaxPos: '1000000000000000' is out of range (at most 1e8: 100 km in mm)");
  }
  EXPECT_THROW(ParseAriaMap("2D-Map\nLINES\n0 0 -1e15 0\n", "far.map"), InputError);
}

TEST(WorldIo, RoundTrip) {
  FloorPlan p;
  p.walls = {{{0, 0}, {5, 0}}, {{5, 0}, {5, 4.25}}};
  p.rooms = {{"room a", {0, 0}, {5, 4.25}}};
  p.doorways = {{"door1", {{5, 1}, {5, 2}}}};
  p.home = Pose2{1, 1, DegToRad(-90)};
  p.route = {{"wp01", {1, 2, DegToRad(45)}}, {"wp02", {3, 2, 0}}};
  const std::string path = ::cogmap::testing_util::TestTempPath("round_trip.map");
  WriteAriaMap(path, p);
  const FloorPlan q = ReadAriaMap(path).plan;
  ASSERT_EQ(q.walls.size(), 2u);
  EXPECT_NEAR(q.walls[1].b.y(), 4.25, 1e-9);
  ASSERT_EQ(q.rooms.size(), 1u);
  EXPECT_EQ(q.rooms[0].name, "room a");
  EXPECT_NEAR(q.rooms[0].max.y(), 4.25, 1e-9);
  ASSERT_EQ(q.doorways.size(), 1u);
  EXPECT_NEAR(q.doorways[0].line.b.y(), 2.0, 1e-9);
  ASSERT_TRUE(q.home.has_value());
  EXPECT_NEAR(q.home->theta, DegToRad(-90), 1e-9);
  ASSERT_EQ(q.route.size(), 2u);
  EXPECT_EQ(q.route[1].name, "wp02");
  EXPECT_NEAR(q.route[0].pose.theta, DegToRad(45), 1e-9);
  std::filesystem::remove(path);
}

TEST(WorldIo, BitmapOutlinesOccupiedPixels) {
  // A 4x3 image with one dark pixel at column 1, row 0 (top).
  GreyImage img{4, 3, std::vector<uint8_t>(12, 255)};
  img.pixels[1] = 0;
  BitmapWorldOptions o;
  o.m_per_pixel = 0.5;
  const FloorPlan p = FloorPlanFromOccupancy(img, o);
  ASSERT_EQ(p.walls.size(), 4u);  // the four sides of the pixel
  // Pixel (1, 0) covers x in [0.5, 1], y in [1, 1.5].
  double xmin = 9, xmax = -9, ymin = 9, ymax = -9;
  for (const auto& w : p.walls)
    for (const Vec2& v : {w.a, w.b}) {
      xmin = std::min(xmin, v.x());
      xmax = std::max(xmax, v.x());
      ymin = std::min(ymin, v.y());
      ymax = std::max(ymax, v.y());
    }
  EXPECT_DOUBLE_EQ(xmin, 0.5);
  EXPECT_DOUBLE_EQ(xmax, 1.0);
  EXPECT_DOUBLE_EQ(ymin, 1.0);
  EXPECT_DOUBLE_EQ(ymax, 1.5);
  ASSERT_TRUE(p.home.has_value());
}

TEST(WorldIo, BitmapRunsMergeIntoLongWalls) {
  GreyImage img{10, 3, std::vector<uint8_t>(30, 255)};
  for (int x = 0; x < 10; ++x) img.pixels[10 + x] = 0;  // the middle row is a wall
  const FloorPlan p = FloorPlanFromOccupancy(img);
  EXPECT_EQ(p.walls.size(), 4u);  // top, bottom, and the two ends
}

TEST(WorldIo, ReadsRoomSegmentationBitmap) {
  const auto r = ReadWorld(kShared + "/data/room-segmentation/lab_a_scan.png");
  EXPECT_GT(r.plan.walls.size(), 100u);
  EXPECT_TRUE(r.plan.home.has_value());
}

TEST(WorldIo, CorruptPngIsAnError) {
  const std::string path = ::cogmap::testing_util::TestTempPath("corrupt.png");
  {
    FILE* f = std::fopen(path.c_str(), "wb");
    std::fputs("\x89PNG\r\n\x1a\nnot really", f);
    std::fclose(f);
  }
  EXPECT_THROW(ReadWorld(path), InputError);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace cogmap::io
