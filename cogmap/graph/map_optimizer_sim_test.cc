// End to end: the simulator drives a world whose walls run along the axes,
// the mapper cuts the run into rooms on drifting odometry, the pose graph
// places them and bends each room's walls by the drift it finds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>

#include "cogmap/asr/mapper.h"
#include "cogmap/core/angles.h"
#include "cogmap/graph/map_optimizer.h"
#include "cogmap/io/world_io.h"
#include "cogmap/mapping/pipeline.h"
#include "cogmap/sim/simulator.h"

namespace cogmap::graph {
namespace {

// The dominant direction of a set of walls modulo a quarter turn (radians,
// within +-45 degrees), each edge weighted by its length.
double DominantDirection(const std::vector<Polyline>& walls) {
  std::complex<double> sum(0.0, 0.0);
  for (const Polyline& line : walls)
    for (size_t i = 1; i < line.size(); ++i) {
      const Vec2 e = line[i] - line[i - 1];
      sum += e.norm() * std::polar(1.0, 4.0 * std::atan2(e.y(), e.x()));
    }
  return std::arg(sum) / 4.0;
}

// nine_rooms at 1 degree per metre of drift (16 sonars): every room's walls
// as the graph places them, and their direction off the world's axes
// (median over the rooms, degrees).
double MedianWallLean(bool bend_where_seen) {
  const FloorPlan plan = io::ReadAriaMap(std::string(COGMAP_SHARED_DIR) + "/worlds/nine_rooms.map").plan;
  const auto robot = sensors::BuiltinRobot("pioneer16");
  sim::SimulatorOptions so;
  so.seed = 1;
  so.odometry.drift_rad_per_m = DegToRad(1.0);
  const asr::MapperOptions mo = mapping::MapperOptionsFor(robot, {});  // the default mode's
  MapOptimizerOptions go;
  go.bend_where_seen = bend_where_seen;
  MapOptimizer opt(go);
  asr::CognitiveMapper mapper(robot, mo, nullptr, [](const asr::Asr&) {});
  mapper.SetPlacer([&opt](asr::Asr a) { return opt.Place(std::move(a)); });
  sim::Simulate(plan, robot, so, [&mapper](const sensors::LogRecord& r) { mapper.Push(r); });
  mapper.Finish();
  const OptimizerResult r = opt.Finish();
  EXPECT_EQ(r.solution, "pose_graph");
  EXPECT_GE(r.asrs.size(), 8u);
  std::vector<double> lean;
  for (const AsrEstimate& e : r.asrs)
    if (!e.corrected_walls.empty())
      lean.push_back(std::abs(RadToDeg(DominantDirection(Transform(e.pose, e.corrected_walls)))));
  std::sort(lean.begin(), lean.end());
  return lean.empty() ? 90.0 : lean[lean.size() / 2];
}

// A room's walls were heard all along its path while the heading drifted;
// bent by the drift where each wall was heard, they run along the world's
// axes again. Bent at the nearest path pose instead, they kept most of the
// lean (the robot hears a wall again and again as it goes, each echo
// drawing it where the drift then puts it). Measured: median lean 2.6
// degrees bent where seen, 4.1 at the nearest pose.
TEST(MapOptimizerOnSimulatedRuns, WallsBentWhereTheyWereSeenRunAlongTheAxes) {
  const double seen = MedianWallLean(true), nearest = MedianWallLean(false);
  // Sonar walls come out 2.5-3 degrees off their true direction even at
  // exact poses (docs/pose-graph.md, "Limits"): the lean left is that.
  EXPECT_LT(seen, 3.0);
  EXPECT_LT(seen, nearest - 1.0) << "nearest-pose bend: " << nearest;
}

}  // namespace
}  // namespace cogmap::graph
