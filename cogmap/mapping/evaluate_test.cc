// `cogmap eval` on a map folder against a bitmap world and its room
// segmentation (issue 11: rooms of real buildings).
#include "cogmap/mapping/evaluate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "cogmap/core/angles.h"
#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/image.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/polyline_io.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::mapping {
namespace {

using ::cogmap::testing_util::TestTempPath;

// Two 4 x 4 m rooms side by side (0.05 m pixels, walls 0.1 m thick), joined
// by a 1 m door in the wall between them; 'closed' draws the door shut (the
// room segmentation's convention).
io::RgbImage TwoRooms(bool closed) {
  const int W = 162, H = 82;
  io::RgbImage img(W, H, io::Rgb{255, 255, 255});
  const io::Rgb black{0, 0, 0};
  for (int x = 0; x < W; ++x)
    for (int row = 0; row < H; ++row) {
      const bool border = x < 2 || x >= W - 2 || row < 2 || row >= H - 2;
      const bool middle = x >= 80 && x < 82 && (closed || row < 31 || row >= 51);
      if (border || middle) img.at(x, row) = black;
    }
  return img;
}

// A laser robot exploring the world from (2, 2) for 'seconds' (seed 'seed'),
// logged as NAME.log and mapped into NAME_map (returned), default options.
std::string MapExplored(const std::string& world_png, const std::string& name, int seed, double seconds) {
  const FloorPlan world = io::ReadWorld(world_png).plan;
  sim::SimulatorOptions so;
  so.mode = sim::SimMode::kExplore;
  so.seed = seed;
  so.max_time_s = seconds;
  so.explore_idle_s = 40.0;
  so.start = Pose2{2.0, 2.0, 0.0};
  const std::string log_path = TestTempPath(name + ".log");
  {
    std::ofstream out(log_path);
    io::NativeLogWriter w(out, sensors::BuiltinRobot("laser"));
    sim::Simulate(world, sensors::BuiltinRobot("laser"), so, [&w](const sensors::LogRecord& r) { w.Write(r); });
  }
  MapJob job;
  job.log_path = log_path;
  job.output_dir = TestTempPath(name + "_map");
  auto log = io::OpenLog(log_path);
  RunMapJob(*log, job);
  return job.output_dir;
}

TEST(EvaluateFolder, RoomsFromASegmentationImage) {
  const std::string world_png = TestTempPath("two_rooms.png"), rooms_png = TestTempPath("two_rooms_gt.png");
  io::WritePng(world_png, TwoRooms(false));
  io::WritePng(rooms_png, TwoRooms(true));
  MapJob job;
  job.output_dir = MapExplored(world_png, "two_rooms", 3, 240.0);

  EvaluateOptions o;
  o.world = world_png;
  o.rooms = rooms_png;
  const nlohmann::json m = EvaluateFolder(job.output_dir, o).metrics;
  // Both rooms were entered, and the plan's rooms are the two rooms.
  ASSERT_TRUE(m["rooms_entered"].is_number());
  EXPECT_EQ(m["rooms_entered"].get<int>(), 2);
  ASSERT_TRUE(m["room_iou_median"].is_number());
  EXPECT_GT(m["room_iou_median"].get<double>(), 0.7);
  EXPECT_DOUBLE_EQ(m["room_recall"].get<double>(), 1.0);
  // Without the image the world (a bitmap) has no rooms to compare with.
  o.rooms.clear();
  EXPECT_TRUE(EvaluateFolder(job.output_dir, o).metrics["room_iou_median"].is_null());
  // An image of another size is not this world's segmentation.
  const std::string other = TestTempPath("other_gt.png");
  io::WritePng(other, io::RgbImage(100, 82, io::Rgb{255, 255, 255}));
  o.rooms = other;
  try {
    EvaluateFolder(job.output_dir, o);
    FAIL() << "a segmentation of another size was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(other), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not the same building"), std::string::npos) << e.what();
  }
}

// The same folder's walls put into the world 3 degrees turned about the
// start (the map's frame off by what a heading error made before the first
// walls were seen): the unaligned precision counts it, the aligned keys see
// the map's shape unchanged and name the turn.
TEST(EvaluateFolder, AlignedWallPrecisionSeesTheShapeAndNamesTheTurn) {
  const std::string world_png = TestTempPath("two_rooms_turn.png");
  io::WritePng(world_png, TwoRooms(false));
  MapJob job;
  job.output_dir = MapExplored(world_png, "two_rooms_turn", 4, 120.0);
  EvaluateOptions o;
  o.world = world_png;
  const nlohmann::json before = EvaluateFolder(job.output_dir, o).metrics;
  ASSERT_TRUE(before["wall_precision_p95_m_aligned"].is_number());
  EXPECT_LT(std::abs(before["map_alignment_deg"].get<double>()), 0.5);

  const std::string walls = job.output_dir + "/walls.json";
  io::WallsFile wf = io::ReadWallsJson(walls);
  wf.world_from_map = Pose2{2.0, 2.0, DegToRad(3.0)} * Pose2{2.0, 2.0, 0.0}.inverse() * wf.world_from_map;
  io::WriteWallsJson(walls, wf);
  const nlohmann::json after = EvaluateFolder(job.output_dir, o).metrics;
  EXPECT_GT(after["wall_precision_p95_m"].get<double>(), before["wall_precision_p95_m"].get<double>() + 0.05);
  EXPECT_NEAR(after["wall_precision_p95_m_aligned"].get<double>(), before["wall_precision_p95_m_aligned"].get<double>(),
              0.01);
  EXPECT_NEAR(after["map_alignment_deg"].get<double>(), before["map_alignment_deg"].get<double>() - 3.0, 0.05);
}

}  // namespace
}  // namespace cogmap::mapping

namespace cogmap::mapping {
namespace {

// A range neither unset nor one a sensor has is an error naming the option,
// before any file is read (NaN fell back to the folder's range silently).
TEST(EvaluateFolder, ARangeThatIsNoNumberIsAnError) {
  EvaluateOptions o;
  o.range_m = std::nan("");
  try {
    EvaluateFolder("no-such-folder", o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--range nan: must be in (0, 1000] metres");
  }
}

}  // namespace
}  // namespace cogmap::mapping
