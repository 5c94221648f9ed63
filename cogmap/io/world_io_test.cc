#include "cogmap/io/world_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/grid_io.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/sim/simulator.h"

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
  // A 4x3 image with one dark pixel at column 1, row 0 (top), 0.5 m pixels:
  // the world is closed by the image's border.
  GreyImage img{4, 3, std::vector<uint8_t>(12, 255)};
  img.pixels[1] = 0;
  BitmapWorldOptions o;
  o.m_per_pixel = 0.5;
  const FloorPlan p = FloorPlanFromOccupancy(img, o);
  // The pixel (1, 0) covers x in [0.5, 1], y in [1, 1.5]: its left, right and
  // bottom sides; its top lies on the border, which has two runs beside it
  // (x 0-0.5 and 1-2); the bottom, left and right borders one each.
  auto has = [&](Vec2 a, Vec2 b) {
    for (const auto& w : p.walls)
      if (((w.a - a).norm() < 1e-12 && (w.b - b).norm() < 1e-12) || ((w.a - b).norm() < 1e-12 && (w.b - a).norm() < 1e-12))
        return true;
    return false;
  };
  EXPECT_EQ(p.walls.size(), 8u);
  EXPECT_TRUE(has({0.5, 1.0}, {0.5, 1.5}));
  EXPECT_TRUE(has({1.0, 1.0}, {1.0, 1.5}));
  EXPECT_TRUE(has({0.5, 1.0}, {1.0, 1.0}));
  EXPECT_TRUE(has({0.0, 1.5}, {0.5, 1.5}));
  EXPECT_TRUE(has({1.0, 1.5}, {2.0, 1.5}));
  EXPECT_TRUE(has({0.0, 0.0}, {2.0, 0.0}));
  EXPECT_TRUE(has({0.0, 1.5}, {0.0, 0.0}) || has({0.0, 0.0}, {0.0, 1.5}));
  EXPECT_TRUE(has({2.0, 1.5}, {2.0, 0.0}) || has({2.0, 0.0}, {2.0, 1.5}));
  // Home: the free pixel farthest from the walls and the border.
  ASSERT_TRUE(p.home.has_value());
  EXPECT_GT(p.home->x, 0.0);
  EXPECT_LT(p.home->x, 2.0);
}

TEST(WorldIo, BitmapRunsMergeIntoLongWalls) {
  GreyImage img{10, 3, std::vector<uint8_t>(30, 255)};
  for (int x = 0; x < 10; ++x) img.pixels[10 + x] = 0;  // the middle row is a wall
  const FloorPlan p = FloorPlanFromOccupancy(img);
  // Each side of the wall row one wall; the border closes the two free rows
  // (top and bottom one each, and the left and right sides of each row).
  EXPECT_EQ(p.walls.size(), 8u);
}

TEST(WorldIo, ReadsRoomSegmentationBitmap) {
  const auto r = ReadWorld(kShared + "/data/room-segmentation/lab_a_scan.png");
  EXPECT_GT(r.plan.walls.size(), 100u);
  EXPECT_TRUE(r.plan.home.has_value());
}

// A 9 x 5 px segmentation, 1 m pixels: grey all round, a white room (3 x 3
// px) and a coloured one (3 x 3 px) either side of a black wall column, and
// a white speck at the top right touching the coloured room only corner to
// corner (4-connected regions: not joined).
TEST(WorldIo, RoomSegmentationLabelsWhiteAndColouredRegions) {
  RgbImage img(9, 5, Rgb{180, 180, 180});
  for (int row = 1; row <= 3; ++row) {
    for (int x = 1; x <= 3; ++x) img.at(x, row) = Rgb{255, 255, 255};
    img.at(4, row) = Rgb{0, 0, 0};
    for (int x = 5; x <= 7; ++x) img.at(x, row) = Rgb{200, 100, 50};
  }
  img.at(8, 0) = Rgb{255, 255, 255};
  const RoomLabels l = RoomLabelsFromSegmentation(img, 1.0, /*min_room_m2=*/2.0);
  ASSERT_EQ(l.names.size(), 2u);  // the speck (1 m2) is no room
  EXPECT_EQ(l.cells, (std::vector<int64_t>{9, 9}));
  // Pixel (x, row) covers x..x+1, 4-row..5-row (row 0 on top, y up).
  EXPECT_EQ(l.At({1.5, 3.5}), 0);   // pixel (1, 1)
  EXPECT_EQ(l.At({3.5, 1.5}), 0);   // pixel (3, 3)
  EXPECT_EQ(l.At({4.5, 2.5}), -1);  // the wall
  EXPECT_EQ(l.At({7.5, 1.5}), 1);
  EXPECT_EQ(l.At({8.5, 4.5}), -1);  // the speck
  EXPECT_EQ(l.At({0.5, 0.5}), -1);  // grey: outside
  EXPECT_EQ(l.At({-0.5, 2.0}), -1);
  EXPECT_EQ(l.At({9.5, 2.0}), -1);
}

TEST(WorldIo, RoomSegmentationOfTheBenchmarkBuilding) {
  // lab_a's ground truth: its rooms with their doors closed.
  const RoomLabels l = ReadRoomSegmentation(kShared + "/data/room-segmentation/lab_a_scan_gt_segmentation.png");
  EXPECT_EQ(l.names.size(), 46u);
  EXPECT_EQ(l.width, 824);
  EXPECT_EQ(l.height, 708);
  int64_t total = 0;
  for (int64_t c : l.cells) total += c;
  EXPECT_GT(total, 300000);  // most of the white floor
  const std::string path = ::cogmap::testing_util::TestTempPath("grey.png");
  WritePng(path, RgbImage(4, 4, Rgb{180, 180, 180}));
  try {
    ReadRoomSegmentation(path);
    FAIL() << "a segmentation without rooms was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no rooms"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
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


// A ROS map_server map as a world: a 4 m x 3 m room (one-pixel walls at
// 0.1 m per pixel) whose lower-left corner sits at the YAML's origin.
std::string WriteRoomMap(const std::string& name, const std::string& image_ext) {
  const int w = 40, h = 30;
  std::vector<uint8_t> px(static_cast<size_t>(w) * h, kPgmFree);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (x == 0 || y == 0 || x == w - 1 || y == h - 1) px[static_cast<size_t>(y) * w + x] = kPgmOccupied;
  px[static_cast<size_t>(5) * w + 5] = kPgmUnknown;  // unknown: neither wall nor free
  const std::string dir = ::cogmap::testing_util::TestTempPath(name);
  std::filesystem::create_directories(dir);
  if (image_ext == ".pgm") {
    PgmImage pgm;
    pgm.width = w;
    pgm.height = h;
    pgm.pixels = px;
    std::ofstream(dir + "/room.pgm", std::ios::binary) << EncodePgm(pgm);
  } else {
    std::ofstream(dir + "/room.png", std::ios::binary) << EncodeGreyPng(w, h, px);
  }
  std::ofstream(dir + "/map.yaml") << "image: room" << image_ext
                                   << "\nresolution: 0.1\norigin: [-1.0, -2.0, 0.0]\nnegate: 0\n"
                                      "occupied_thresh: 0.65\nfree_thresh: 0.196\n";
  return dir + "/map.yaml";
}

void ExpectRoomWorld(const FloorPlan& p) {
  // The inner outline of the one-pixel border (its outer side meets the
  // image's border, itself a wall), plus the unknown pixel's nothing: 4
  // segments.
  EXPECT_EQ(p.walls.size(), 4u);
  double xmin = 9, xmax = -9, ymin = 9, ymax = -9;
  for (const auto& wall : p.walls)
    for (const Vec2& v : {wall.a, wall.b}) {
      xmin = std::min(xmin, v.x());
      xmax = std::max(xmax, v.x());
      ymin = std::min(ymin, v.y());
      ymax = std::max(ymax, v.y());
    }
  EXPECT_NEAR(xmin, -0.9, 1e-12);
  EXPECT_NEAR(xmax, 2.9, 1e-12);
  EXPECT_NEAR(ymin, -1.9, 1e-12);
  EXPECT_NEAR(ymax, 0.9, 1e-12);
  EXPECT_NEAR(p.min.x(), -1.0, 1e-12);
  EXPECT_NEAR(p.max.y(), 1.0, 1e-12);
  ASSERT_TRUE(p.home.has_value());
  EXPECT_GT(p.home->x, -0.9);
  EXPECT_LT(p.home->x, 2.9);
  EXPECT_GT(p.home->y, -1.9);
  EXPECT_LT(p.home->y, 0.9);
}

TEST(WorldIo, RosMapYamlWithPgmIsAWorld) {
  const auto r = ReadWorld(WriteRoomMap("rosmap_pgm", ".pgm"));
  ExpectRoomWorld(r.plan);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(WorldIo, RosMapYamlWithPngIsAWorld) { ExpectRoomWorld(ReadWorld(WriteRoomMap("rosmap_png", ".png")).plan); }

TEST(WorldIo, RosMapOriginYawRotatesTheWorld) {
  const std::string yaml = WriteRoomMap("rosmap_yaw", ".pgm");
  std::ofstream(yaml) << "image: room.pgm\nresolution: 0.1\norigin: [1.0, 2.0, 1.5707963267948966]\n";
  const FloorPlan p = ReadWorld(yaml).plan;
  // Image x runs along map y: the 4 m side now spans y 2..6, x -2..1.
  EXPECT_NEAR(p.min.x(), -2.0, 1e-9);
  EXPECT_NEAR(p.max.x(), 1.0, 1e-9);
  EXPECT_NEAR(p.min.y(), 2.0, 1e-9);
  EXPECT_NEAR(p.max.y(), 6.0, 1e-9);
}

TEST(WorldIo, RosMapProblemsNameTheFile) {
  const std::string yaml = WriteRoomMap("rosmap_bad", ".pgm");
  std::ofstream(yaml) << "image: room.pgm\nresolution: -0.1\norigin: [0, 0, 0]\n";
  try {
    ReadWorld(yaml);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("map.yaml:2: 'resolution' must be positive"), std::string::npos) << e.what();
  }
  std::ofstream(yaml) << "image: missing.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n";
  try {
    ReadWorld(yaml);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.pgm"), std::string::npos) << e.what();
  }
}

// Simulated from a given start, a noiseless laser sees the room's inner walls
// exactly: every beam's range is the distance along the beam to the
// rectangle [-0.9, 2.9] x [-1.9, 0.9].
TEST(WorldIo, RosMapWorldSimulatesReadingsOnItsWalls) {
  const FloorPlan plan = ReadWorld(WriteRoomMap("rosmap_sim", ".pgm")).plan;
  const sensors::RobotDescription robot = sensors::BuiltinRobot("laser");
  sim::SimulatorOptions o;
  o.mode = sim::SimMode::kExplore;
  o.start = Pose2{0.5, -0.5, DegToRad(30.0)};
  o.max_time_s = 4.0;
  o.odometry = sim::OdometryNoiseOptions{0, 0, 0, 0, 0};
  o.sensor.laser_range_sigma_m = 0;
  std::vector<sensors::LogRecord> run;
  sim::Simulate(plan, robot, o, [&](const sensors::LogRecord& r) { run.push_back(r); });
  ASSERT_FALSE(run.empty());
  ASSERT_TRUE(run.front().truth);
  EXPECT_NEAR(run.front().truth->x, 0.5, 1e-9);
  EXPECT_NEAR(run.front().truth->theta, DegToRad(30.0), 1e-9);
  long checked = 0;
  for (const auto& r : run) {
    for (const auto& q : r.ranges) {
      const Pose2 s = *r.truth * robot.sensors[q.sensor].robot_from_sensor;
      const double c = std::cos(s.theta), d = std::sin(s.theta);
      double t = 1e9;
      if (c > 1e-12) t = std::min(t, (2.9 - s.x) / c);
      if (c < -1e-12) t = std::min(t, (-0.9 - s.x) / c);
      if (d > 1e-12) t = std::min(t, (0.9 - s.y) / d);
      if (d < -1e-12) t = std::min(t, (-1.9 - s.y) / d);
      ASSERT_NEAR(q.range_m, t, 1e-6) << "sensor " << q.sensor;
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
}

}  // namespace
}  // namespace cogmap::io
