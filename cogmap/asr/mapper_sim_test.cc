// End to end: the simulator drives the project's worlds, the mapper cuts the
// run into ASRs, the room metrics compare them with the worlds' Room truth
// (issue 5's acceptance runs, 16-sonar Pioneer, no drift).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "cogmap/asr/mapper.h"
#include "cogmap/core/angles.h"
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

// A ring that looks only forward (the Pioneer's 8 front sonars), noiseless
// odometry and ranges on nine_rooms, whose walls all lie at 0 or 90 degrees:
// each room's orientation (Asr::grid_orientation, in the odometry frame,
// which here is the world's) leans with the way the robot drove round the
// room on the axis grid, each echo placed on its unit's axis; on the cone
// grid, the echo on its arc where the wall is, it leans far less.
TEST(MapperOnSimulatedRuns, AForwardRingsRoomsAreSquarerOnItsConeGrid) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const auto robot = sensors::BuiltinRobot("pioneer8");
  ASSERT_TRUE(sensors::SeesOnlyForward(robot));
  auto median_lean_deg = [&](bool from_cone) {
    MapperOptions o;
    o.cone_output_walls = true;
    o.orientation_from_cone = from_cone;
    sim::SimulatorOptions so;
    so.seed = 1;
    so.odometry = sim::OdometryNoiseOptions{0, 0, 0, 0, 0};
    so.sensor.sonar_range_sigma_m = so.sensor.sonar_range_sigma_frac = 0;
    so.sensor.sonar_crosstalk_probability = 0;
    std::vector<double> lean;
    MemoryAsrStore store;
    CognitiveMapper mapper(robot, o, &store, [&lean](const Asr& a) {
      if (!a.grid_orientation.valid) return;
      const double world = a.grid_orientation.angle_rad + a.world_from_local_raw.theta;
      lean.push_back(std::abs(RadToDeg(std::remainder(world, kPi / 2.0))));
    });
    sim::Simulate(plan, robot, so, [&mapper](const sensors::LogRecord& r) { mapper.Push(r); });
    mapper.Finish();
    EXPECT_GE(lean.size(), 8u);
    std::sort(lean.begin(), lean.end());
    return lean.empty() ? 90.0 : lean[lean.size() / 2];
  };
  const double axis = median_lean_deg(false), cone = median_lean_deg(true);
  EXPECT_GT(axis, 2.0);  // measured 2.56 deg
  EXPECT_LT(cone, 1.5);  // measured 1.07 deg
  EXPECT_LT(cone, 0.6 * axis);
}

// The spread (radians, circular 1-sigma) of an ASR's wall directions about
// their dominant one, each edge weighted by its length, modulo a quarter
// turn: the walls of an axis-aligned room mapped on drifting odometry fan
// out by the heading drifted while it was mapped.
double WallDirectionSpread(const Asr& a) {
  std::complex<double> sum(0.0, 0.0);
  double total = 0.0;
  for (const Polyline& line : a.walls_local)
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 e = line[i] - line[i - 1];
      const double len = e.norm();
      sum += len * std::polar(1.0, 4.0 * std::atan2(e.y(), e.x()));
      total += len;
    }
  if (total <= 0.0) return 0.0;
  return std::sqrt(-2.0 * std::log(std::abs(sum) / total)) / 4.0;
}

// The pre-bend: rooms mapped with the odometry's drift removed as it comes
// (the rate the pose graph would hand over, here the true one) have walls
// as square as without drift; on the raw odometry they fan out.
TEST(MapperOnSimulatedRuns, PreBendAtTheDriftKeepsTheWallsSquare) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const auto robot = sensors::BuiltinRobot("laser");
  const double drift = DegToRad(3.0);
  auto spread = [&](bool pre_bend) -> double {
    sim::SimulatorOptions so;
    so.seed = 7;
    so.odometry.drift_rad_per_m = drift;
    so.odometry.scale_error = 0.0;
    std::vector<Asr> asrs;
    CognitiveMapper mapper(robot, {}, nullptr, [&asrs](const Asr& a) { asrs.push_back(a); });
    std::vector<int> asked;
    if (pre_bend) mapper.SetPreBend(2, [&](int placed) {
      asked.push_back(placed);
      return drift;
    });
    sim::Simulate(plan, robot, so, [&mapper](const sensors::LogRecord& r) { mapper.Push(r); });
    mapper.Finish();
    double sum = 0.0;
    int n = 0;
    for (const Asr& a : asrs) {
      EXPECT_EQ(a.pre_bend_rad_per_m, pre_bend && a.id >= 2 ? drift : 0.0) << a.id;
      if (a.id < 2 || a.walls_local.empty()) continue;
      sum += WallDirectionSpread(a);
      ++n;
    }
    if (pre_bend) {
      // Asked once per room from the third on, for the room two back.
      EXPECT_EQ(asked.size(), asrs.size() - 2);
      for (size_t k = 0; k < asked.size(); ++k) EXPECT_EQ(asked[k], static_cast<int>(k));
    }
    EXPECT_GE(n, 6);
    return sum / std::max(n, 1);
  };
  const double raw = spread(false), bent = spread(true);
  EXPECT_GT(raw, DegToRad(2.0));
  EXPECT_LT(bent, 0.6 * raw);
}

}  // namespace
}  // namespace cogmap::asr
