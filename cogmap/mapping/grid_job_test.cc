// `cogmap grid` as a library call, on a corridor log built in code.
#include "cogmap/mapping/grid_job.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "cogmap/core/error.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/mapping/job_test_util.h"

namespace cogmap::mapping {
namespace {

using ::cogmap::testing_util::TestTempPath;
using testing_util::CorridorRecords;
using testing_util::WriteCorridorLog;

grid::CellClass ClassAt(const grid::RangeFusion& f, double x, double y) {
  const auto c = f.limits().CellOf(Vec2(x, y));
  return f.Classify(c.x(), c.y());
}

TEST(GridJob, FusesEveryRecordAndWritesThePictureAndMapServerPair) {
  const std::string log_path = WriteCorridorLog("grid_corridor.log", CorridorRecords());
  auto log = io::OpenLog(log_path);
  GridJob job;
  job.log_path = log_path;
  job.picture_path = TestTempPath("grid_corridor.png");
  job.pgm_base = TestTempPath("grid_corridor_map");
  job.summarize = true;
  const GridJobResult r = RunGridJob(*log, job);
  EXPECT_EQ(r.records, 81);
  EXPECT_EQ(r.readings, 81 * 19);
  EXPECT_EQ(r.robot.name, "corridor-laser");  // the log's own robot
  ASSERT_TRUE(r.fusion);
  EXPECT_EQ(r.fusion->rule(), grid::FusionRule::kMhimm);
  EXPECT_DOUBLE_EQ(r.fusion->limits().cell_m(), 0.1);
  // The robot's path, the free corridor beside it, a wall cell behind y = 1.
  EXPECT_EQ(ClassAt(*r.fusion, 3.0, 0.0), grid::CellClass::kRobotPath);
  EXPECT_EQ(ClassAt(*r.fusion, 3.0, 0.5), grid::CellClass::kEmpty);
  EXPECT_EQ(ClassAt(*r.fusion, 3.0, -0.5), grid::CellClass::kEmpty);
  EXPECT_EQ(ClassAt(*r.fusion, 3.0, 1.05), grid::CellClass::kOccupied);
  EXPECT_EQ(ClassAt(*r.fusion, 3.0, -1.05), grid::CellClass::kOccupied);
  ASSERT_TRUE(r.summary);
  EXPECT_EQ(r.summary->cells, static_cast<long>(r.fusion->limits().width()) * r.fusion->limits().height());
  EXPECT_GT(r.summary->occupied, 0);
  EXPECT_TRUE(std::filesystem::exists(job.picture_path));
  EXPECT_TRUE(std::filesystem::exists(job.pgm_base + ".pgm"));
  EXPECT_TRUE(std::filesystem::exists(job.pgm_base + ".yaml"));
}

TEST(GridJob, TruthPosesPlaceTheWallsWhereTheyAre) {
  // Odometry 0.5 m off to the left: the odometry grid has the walls there, the
  // truth grid where they are.
  const std::string log_path = WriteCorridorLog("grid_offset.log", CorridorRecords(81, Vec2(0.0, 0.5)));
  GridJob job;
  job.picture_path = TestTempPath("grid_offset.svg");
  auto odom_log = io::OpenLog(log_path);
  const GridJobResult odom = RunGridJob(*odom_log, job);
  EXPECT_EQ(ClassAt(*odom.fusion, 3.0, 1.55), grid::CellClass::kOccupied);
  EXPECT_EQ(ClassAt(*odom.fusion, 3.0, 0.5), grid::CellClass::kRobotPath);
  job.use_truth = true;
  auto truth_log = io::OpenLog(log_path);
  const GridJobResult truth = RunGridJob(*truth_log, job);
  EXPECT_EQ(ClassAt(*truth.fusion, 3.0, 1.05), grid::CellClass::kOccupied);
  EXPECT_EQ(ClassAt(*truth.fusion, 3.0, 0.0), grid::CellClass::kRobotPath);
  EXPECT_FALSE(truth.summary);
}

TEST(GridJob, RejectsBadOptionsBeforeWritingAnything) {
  const std::string log_path = WriteCorridorLog("grid_bad.log", CorridorRecords(5));
  GridJob job;
  job.picture_path = TestTempPath("grid_bad.txt");
  auto log = io::OpenLog(log_path);
  EXPECT_THROW(RunGridJob(*log, job), InputError);  // not a picture format
  EXPECT_FALSE(std::filesystem::exists(job.picture_path));
  job.picture_path = TestTempPath("grid_bad.png");
  job.cell_m = 0.0;
  try {
    job.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "--cell 0: must be in (0, 10] metres");
  }
  job.cell_m = 0.1;
  job.px_per_cell = 65;
  EXPECT_THROW(job.Validate(), InputError);
  job.px_per_cell = 0;
  job.robot_spec = "pioneer8";  // 8 sensors: the log's beam 18 is not one of them
  auto log2 = io::OpenLog(log_path);
  EXPECT_THROW(RunGridJob(*log2, job), InputError);
  EXPECT_FALSE(std::filesystem::exists(job.picture_path));
}

}  // namespace
}  // namespace cogmap::mapping
