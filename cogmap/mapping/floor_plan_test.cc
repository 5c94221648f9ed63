// The floor plan of a store equals the plan.json that `cogmap map` wrote.
#include "cogmap/mapping/floor_plan.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "cogmap/core/angles.h"
#include "cogmap/core/test_temp.h"
#include "cogmap/io/log_reader.h"
#include "cogmap/io/native_log.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/map_job.h"
#include "cogmap/plan/plan_json.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::mapping {
namespace {

using ::cogmap::testing_util::TestTempPath;

TEST(FloorPlanOfStore, EqualsThePlanJsonOfTheMapJob) {
  // Two minutes of a simulated nine_rooms run with 1 deg/m of drift.
  const FloorPlan world = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  sim::SimulatorOptions so;
  so.seed = 4;
  so.max_time_s = 120.0;
  so.odometry.drift_rad_per_m = DegToRad(1.0);
  const std::string log_path = TestTempPath("plan_run.log");
  {
    std::ofstream out(log_path);
    io::NativeLogWriter w(out, sensors::BuiltinRobot("pioneer16"));
    sim::Simulate(world, sensors::BuiltinRobot("pioneer16"), so, [&w](const sensors::LogRecord& r) { w.Write(r); });
  }
  MapJob job;
  job.log_path = log_path;
  job.outputs = OutputChoice::Parse("svg");
  job.output_dir = TestTempPath("plan_map");
  auto log = io::OpenLog(log_path);
  const MapJobSummary s = RunMapJob(*log, job);
  ASSERT_GE(s.asrs, 2);
  ASSERT_GE(s.plan_rooms, 1);

  auto store = asr::SqliteAsrStore::Open(job.output_dir + "/map.sqlite", asr::SqliteAsrStore::OpenMode::kReadOnly);
  const plan::Plan p = FloorPlanOfStore(*store);
  EXPECT_EQ(static_cast<int>(p.rooms.size()), s.plan_rooms);
  EXPECT_EQ(static_cast<int>(p.walls.size()), s.plan_walls);
  EXPECT_EQ(static_cast<int>(p.doors.size()), s.plan_doors);
  std::ifstream in(job.output_dir + "/plan.json");
  std::stringstream written;
  written << in.rdbuf();
  EXPECT_EQ(plan::PlanToJsonText(p), written.str());

  // The plan built from inputs it releases is the same plan, and it empties
  // exactly what it says it does.
  std::vector<asr::Asr> all;
  std::map<int, int> room_of;
  std::map<int, std::vector<Pose2>> placed;
  for (int id : store->Ids()) {
    all.push_back(*store->Get(id));
    room_of[id] = store->RoomOf(id);
    if (auto pl = store->GetPlacement(id)) placed[id] = pl->corrected_path;
  }
  // With the options the store carries (the robot's radius, reach and beam),
  // as `cogmap map` plans.
  const plan::PlanOptions options = PlanOptionsOfStore(*store);
  const std::string kept = plan::PlanToJsonText(plan::BuildPlan(all, room_of, options, placed));
  EXPECT_EQ(kept, written.str());
  const std::vector<asr::Asr> before = all;
  ASSERT_FALSE(placed.empty());
  EXPECT_EQ(plan::PlanToJsonText(plan::BuildPlanReleasing(&all, room_of, options, &placed)), kept);
  EXPECT_TRUE(placed.empty());
  ASSERT_EQ(all.size(), before.size());
  for (size_t i = 0; i < all.size(); ++i) {
    EXPECT_TRUE(all[i].walls_local.empty() && all[i].path.empty() && all[i].free_hull_local.empty());
    EXPECT_EQ(all[i].id, before[i].id);
    EXPECT_EQ(all[i].exits.size(), before[i].exits.size());
    EXPECT_EQ(all[i].start_time_s, before[i].start_time_s);
    EXPECT_EQ(all[i].bytes.grid, before[i].bytes.grid);
  }
}

TEST(FloorPlanOfStore, AnEmptyStoreHasAnEmptyPlan) {
  asr::MemoryAsrStore store;
  const plan::Plan p = FloorPlanOfStore(store);
  EXPECT_TRUE(p.walls.empty());
  EXPECT_TRUE(p.rooms.empty());
  EXPECT_TRUE(p.doors.empty());
  EXPECT_TRUE(p.edges.empty());
}

}  // namespace
}  // namespace cogmap::mapping
