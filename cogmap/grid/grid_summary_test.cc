#include "cogmap/grid/grid_summary.h"

#include <gtest/gtest.h>

namespace cogmap::grid {
namespace {

GridBounds Box() {
  GridBounds b;
  b.fixed = MapLimits(0.1, Vec2(-4, -4), 80, 80);
  return b;
}

TEST(GridSummary, CountsClassesOfSingleSpot) {
  HimmFusion g(true, MhimmOptions{}, Box());
  const Pose2 robot{0.05, 0.05, 0};
  g.MarkRobot(robot);
  for (int i = 0; i < 3; ++i) g.Insert(robot, sensors::RangeSensor{}, 1.0);
  const GridSummary s = Summarize(g);
  EXPECT_EQ(s.cells, 6400);
  EXPECT_EQ(s.occupied, 1);     // t = 9
  EXPECT_EQ(s.robot_path, 1);
  EXPECT_EQ(s.empty, 8);        // beam cells 41..48 at -3
  EXPECT_EQ(s.touched, 1 + 1 + 8 + 8);
  EXPECT_EQ(s.line_fraction, 0.0);
  EXPECT_GT(s.mean_entropy_bits, 0.0);
}

TEST(GridSummary, StraightWallIsALine) {
  HimmFusion g(true, MhimmOptions{}, Box());
  sensors::RangeSensor left;
  left.robot_from_sensor.theta = 1.5707963267948966;
  for (int k = 0; k < 30; ++k) {
    const Pose2 robot{-1.45 + 0.1 * k, 0.05, 0};
    g.MarkRobot(robot);
    for (int i = 0; i < 3; ++i) g.Insert(robot, left, 1.0);
  }
  const GridSummary s = Summarize(g);
  // Row 50 gets the hits, rows 49 and 51 the neighbours' 1.5s: a wall three
  // cells thick, every occupied cell on a line except the row ends.
  long in_rows = 0;
  for (int y = 49; y <= 51; ++y)
    for (int x = 0; x < 80; ++x) in_rows += g.Classify(x, y) == CellClass::kOccupied;
  EXPECT_EQ(s.occupied, in_rows);
  EXPECT_GE(s.occupied, 3 * 28);
  EXPECT_GT(s.line_fraction, 0.9);
}

}  // namespace
}  // namespace cogmap::grid
