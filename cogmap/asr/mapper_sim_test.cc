// End to end: the simulator drives the project's worlds, the mapper cuts the
// run into ASRs, the room metrics compare them with the worlds' Room truth
// (issue 5's acceptance runs, 16-sonar Pioneer, no drift).
#include <gtest/gtest.h>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/room_metrics.h"
#include "cogmap/io/world_io.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::asr {
namespace {

std::vector<Asr> MapWorld(const std::string& world, const MapperOptions& options) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/" + world).plan;
  const auto robot = sensors::BuiltinRobot("pioneer16");
  sim::SimulatorOptions so;
  so.seed = 7;
  so.odometry.drift_rad_per_m = 0.0;
  so.odometry.scale_error = 0.0;
  std::vector<Asr> asrs;
  MemoryAsrStore store;
  CognitiveMapper mapper(robot, options, &store, [&asrs](const Asr& a) { asrs.push_back(a); });
  sim::Simulate(plan, robot, so, [&mapper](const sensors::LogRecord& r) { mapper.Push(r); });
  mapper.Finish();
  EXPECT_EQ(store.Count(), static_cast<int>(asrs.size()));
  return asrs;
}

TEST(MapperOnSimulatedRuns, NineRoomsGivesOneAsrPerRoom) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const auto asrs = MapWorld("nine_rooms.map", {});
  const RoomMetrics m = EvaluateRooms(asrs, plan.rooms);
  EXPECT_GE(m.room_precision, 0.9);
  EXPECT_GE(m.room_recall, 0.9);
}

TEST(MapperOnSimulatedRuns, HallwayInFixedLengthModeGivesAsrsOfTheSetLength) {
  MapperOptions o;
  o.boundary.mode = BoundaryMode::kFixedLength;
  o.boundary.asr_length_m = 4.0;
  const auto asrs = MapWorld("hallway_loop.map", o);
  ASSERT_GE(asrs.size(), 40u);
  for (size_t i = 0; i + 1 < asrs.size(); ++i) {  // the last one is the remainder
    double length = 0.0;
    const auto& p = asrs[i].path;
    for (size_t k = 1; k < p.size(); ++k) length += (p[k].translation() - p[k - 1].translation()).norm();
    EXPECT_NEAR(length, 4.0, 0.1) << "ASR " << i;
  }
}

}  // namespace
}  // namespace cogmap::asr
