#include "cogmap/eval/plan_metrics.h"

#include <gtest/gtest.h>

namespace cogmap::eval {
namespace {

plan::Wall W(Vec2 a, Vec2 b) {
  plan::Wall w;
  w.points = {a, b};
  return w;
}

plan::Room R(int id, std::vector<Vec2> poly) {
  plan::Room r;
  r.id = id;
  r.polygon = std::move(poly);
  return r;
}

// Truth: a 4 x 4 m room's four walls; three named rooms. The plan: three of
// the walls, the bottom one drawn a second time 0.1 m off over x = 1..3, and
// two rooms, the second reaching 1 m into the first.
struct Case {
  FloorPlan truth;
  plan::Plan plan;
  Case() {
    truth.walls = {{{0, 0}, {4, 0}}, {{4, 0}, {4, 4}}, {{4, 4}, {0, 4}}, {{0, 4}, {0, 0}}};
    truth.rooms = {{"a", {0, 0}, {4, 4}}, {"b", {4, 0}, {8, 4}}, {"c", {20, 20}, {24, 24}}};
    plan.walls = {W({0, 0}, {4, 0}), W({1, 0.1}, {3, 0.1}), W({0, 0}, {0, 4}), W({4, 0}, {4, 4})};
    plan.rooms = {R(0, {{0, 0}, {4, 0}, {4, 4}, {0, 4}}), R(1, {{3, 0}, {8, 0}, {8, 4}, {3, 4}})};
  }
};

// Rooms from a segmentation raster (0.1 m cells over 10 x 10 m): the lower
// half is room 0, the upper half room 1, a 1 m band between them no room.
// One plan room covers room 0 exactly, another half of room 1 and the band.
TEST(PlanMetrics, RoomsFromASegmentationRaster) {
  RoomLabels l;
  l.cell_m = 0.1;
  l.width = l.height = 100;
  l.label.assign(100 * 100, -1);
  l.names = {"room 1", "room 2"};
  l.cells = {0, 0};
  for (int y = 0; y < 100; ++y)
    for (int x = 0; x < 100; ++x) {
      const int r = y < 45 ? 0 : y >= 55 ? 1 : -1;
      l.label[y * 100 + x] = r;
      if (r >= 0) ++l.cells[r];
    }
  Case c;
  c.plan.rooms = {R(0, {{0, 0}, {10, 0}, {10, 4.5}, {0, 4.5}}), R(1, {{0, 4.5}, {10, 4.5}, {10, 7.7}, {0, 7.7}})};
  const PlanMetrics m = EvaluatePlan(c.plan, c.truth, {{5, 8}}, {}, &l);
  ASSERT_EQ(m.room_iou.size(), 2u);
  EXPECT_NEAR(m.room_iou[0], 1.0, 1e-9);
  // Room 2: 45 m2, of which the plan room covers 22 m2 (the rows whose
  // centres lie below 7.7 m: 55-76); the plan room is 32 m2: 22 / (45 + 32 - 22).
  EXPECT_NEAR(m.room_iou[1], 0.4, 1e-9);
  EXPECT_EQ(m.room_entered, (std::vector<bool>{false, true}));
  EXPECT_EQ(m.rooms_entered, 1);
  ASSERT_TRUE(m.room_iou_median_entered.has_value());
  EXPECT_NEAR(*m.room_iou_median_entered, 0.4, 1e-9);
  EXPECT_NEAR(*m.room_iou_median, 0.5 * (1.0 + 0.4), 1e-9);
  // Without the raster the world's room cairns are used.
  EXPECT_EQ(EvaluatePlan(c.plan, c.truth, {{5, 8}}).room_iou.size(), 3u);
}

// A ring corridor 2 m wide around a walled 6 x 6 m block: its room cairn is
// the 10 x 10 m box, the block included. The true room is the floor the robot
// could reach: 100 x 100 cells of 0.1 m less the block's 59 x 59 inside ones
// (its wall cells border the corridor) and the outer corner cell (0, 0), a
// wall cell with no floor beside it: 65.18 m2.
TEST(PlanMetrics, RingCorridorIsItsReachableFloorNotItsBox) {
  FloorPlan truth;
  truth.walls = {{{0, 0}, {10, 0}}, {{10, 0}, {10, 10}}, {{10, 10}, {0, 10}}, {{0, 10}, {0, 0}},
                 {{2, 2}, {8, 2}},  {{8, 2}, {8, 8}},    {{8, 8}, {2, 8}},    {{2, 8}, {2, 2}}};
  truth.rooms = {{"corridor", {0, 0}, {10, 10}}};
  const std::vector<Vec2> path = {{1, 1}, {9, 1}, {9, 9}, {1, 9}};
  plan::Plan arm, square;
  arm.rooms = {R(0, {{0, 0}, {10, 0}, {10, 2}, {0, 2}})};
  square.rooms = {R(0, {{0, 0}, {10, 0}, {10, 10}, {0, 10}})};
  const double floor = 65.18;
  const PlanMetrics a = EvaluatePlan(arm, truth, path);
  ASSERT_EQ(a.room_iou.size(), 1u);
  EXPECT_NEAR(a.room_iou[0], 19.99 / (floor + 20.0 - 19.99), 1e-9);  // the box would give 0.2
  const PlanMetrics b = EvaluatePlan(square, truth, path);
  EXPECT_NEAR(b.room_iou[0], floor / 100.0, 1e-9);  // the box would give 1
  // Never entered: the box is all that is known of the room.
  const PlanMetrics c = EvaluatePlan(arm, truth, {{20, 20}});
  EXPECT_NEAR(c.room_iou[0], 0.2, 1e-12);
}

TEST(PlanMetrics, HandBuiltPlanAgainstTruth) {
  Case c;
  const PlanMetrics m = EvaluatePlan(c.plan, c.truth, {{2, 2}});
  EXPECT_EQ(m.walls, 4);
  EXPECT_EQ(m.rooms, 2);
  EXPECT_DOUBLE_EQ(m.wall_length_m, 14.0);
  EXPECT_DOUBLE_EQ(m.vertices_per_m, 8.0 / 14.0);
  // 280 samples: 240 on a true wall, 40 at 0.1 m.
  EXPECT_EQ(m.samples, 280);
  ASSERT_TRUE(m.precision_p50_m && m.precision_p95_m);
  EXPECT_NEAR(*m.precision_p50_m, 0.0, 1e-12);
  EXPECT_NEAR(*m.precision_p95_m, 0.1, 1e-12);
  // 14 m of plan wall on 12 m of true wall (the top wall is missing).
  EXPECT_NEAR(m.matched_plan_length_m, 14.0, 1e-9);
  EXPECT_NEAR(m.covered_true_length_m, 12.0, 1e-9);
  ASSERT_TRUE(m.duplication);
  EXPECT_NEAR(*m.duplication, 14.0 / 12.0, 1e-9);
  // IoU: room a 1, room b 16 / 20, room c unseen 0.
  ASSERT_EQ(m.room_iou.size(), 3u);
  EXPECT_NEAR(m.room_iou[0], 1.0, 1e-12);
  EXPECT_NEAR(m.room_iou[1], 0.8, 1e-12);
  EXPECT_NEAR(m.room_iou[2], 0.0, 1e-12);
  ASSERT_TRUE(m.room_iou_median);
  EXPECT_NEAR(*m.room_iou_median, 0.8, 1e-12);
  // The path (one point, in room a) enters room a only.
  EXPECT_EQ(m.room_entered, (std::vector<bool>{true, false, false}));
  EXPECT_EQ(m.rooms_entered, 1);
  ASSERT_TRUE(m.room_iou_median_entered);
  EXPECT_NEAR(*m.room_iou_median_entered, 1.0, 1e-12);
  EXPECT_NEAR(m.room_overlap_m2, 4.0, 1e-9);
  // Recall: 12 of 16 m, plus the top wall's 0.2 m next to each side wall.
  EXPECT_GT(m.recall, 12.0 / 16.0);
  EXPECT_LT(m.recall, 12.5 / 16.0);
}

TEST(PlanMetrics, RoomsNeverEnteredAreLeftOutOfTheEnteredMedian) {
  Case c;
  // A path through rooms a and b (and beyond the boxes' edges, entering neither c nor more).
  const PlanMetrics m = EvaluatePlan(c.plan, c.truth, {{2, 2}, {6, 2}, {10, 2}});
  EXPECT_EQ(m.rooms_entered, 2);
  ASSERT_TRUE(m.room_iou_median_entered);
  EXPECT_NEAR(*m.room_iou_median_entered, 0.5 * (m.room_iou[0] + m.room_iou[1]), 1e-12);
  // No path: nothing entered, the median over entered rooms is undefined.
  const PlanMetrics none = EvaluatePlan(c.plan, c.truth, {});
  EXPECT_EQ(none.rooms_entered, 0);
  EXPECT_FALSE(none.room_iou_median_entered.has_value());
}

TEST(PlanMetrics, PerpendicularWallsDoNotMatch) {
  // A plan wall across a true wall's end does not count as lying on it.
  FloorPlan truth;
  truth.walls = {{{0, 0}, {4, 0}}};
  plan::Plan plan;
  plan.walls = {W({2, -0.25}, {2, 0.25})};
  const PlanMetrics m = EvaluatePlan(plan, truth, {});
  EXPECT_EQ(m.matched_plan_length_m, 0.0);
  EXPECT_EQ(m.covered_true_length_m, 0.0);
  EXPECT_FALSE(m.duplication.has_value());
}

TEST(PlanMetrics, OverlapOfCrossingShapesIsExact) {
  // A 4 x 4 square and a triangle with its apex inside it: (2, 2), (6, 0),
  // (6, 4). Inside the square the triangle is the part x in [2, 4] with
  // |y - 2| <= (x - 2) / 2: 2 m^2.
  plan::Plan plan;
  plan.rooms = {R(0, {{0, 0}, {4, 0}, {4, 4}, {0, 4}}), R(1, {{2, 2}, {6, 0}, {6, 4}})};
  EXPECT_NEAR(DescribePlan(plan).room_overlap_m2, 2.0, 1e-12);
  // A room inside another overlaps by its whole area (an L of 3 m^2 in a 4 x 4).
  plan.rooms[1] = R(1, {{1, 1}, {3, 1}, {3, 2}, {2, 2}, {2, 3}, {1, 3}});
  EXPECT_NEAR(DescribePlan(plan).room_overlap_m2, 3.0, 1e-12);
  // Two rooms sharing a wall, one with a vertex on the other's edge: none.
  plan.rooms[1] = R(1, {{4, 1}, {6, 1}, {6, 3}, {4, 3}, {4, 2}});
  EXPECT_EQ(DescribePlan(plan).room_overlap_m2, 0.0);
}

TEST(PlanMetrics, RoomsAlongOneSlantedWallDoNotOverlap) {
  // Two rooms of a generated 100-room building's plan (m): they meet along a
  // wall at 1.7 degrees, their edges there on one line to 1e-5 m. Boost 1.74's
  // intersection reported the whole first room (2.848 m^2) as inside the
  // second; by sampling, and here, they do not overlap.
  plan::Plan plan;
  plan.rooms = {
      R(0, {{41.7146, 0.746486}, {41.7144, 0.768044}, {41.7104, 1.16802}, {41.7101, 1.20099}, {41.6796, 1.21368},
            {41.0071, 1.49397}, {40.9954, 2.66095}, {40.9948, 2.71922}, {40.9373, 2.70979}, {40.0071, 2.55714},
            {40.0665, 2.54081}, {39.8559, 2.50034}, {39.6973, 2.46986}, {39.6975, 2.44795}, {39.7113, 1.06315},
            {39.9058, 0.777685}, {39.9584, 0.700474}, {40.165, 0.702539}, {40.1666, 0.702556}, {40.2645, 0.703535}}),
      R(1, {{39.7315, -0.571659}, {40.2459, -2.16171}, {40.2513, -2.17853}, {40.2662, -2.1882}, {40.5519, -2.37462},
            {40.6511, -2.7549}, {40.6565, -2.77589}, {40.6756, -2.78623}, {45.2004, -5.24109}, {45.2118, -5.24727},
            {45.2247, -5.24714}, {45.4247, -5.24514}, {45.4685, -5.2447}, {45.4739, -5.20125}, {46.2138, 0.806452},
            {46.2221, 0.873586}, {46.1554, 0.861799}, {45.5565, 0.755801}, {45.4051, 0.729007}, {45.5433, 0.661623},
            {45.7549, 0.558456}, {44.9103, 0.550006}, {45.3844, 0.758802}, {45.6081, 0.859667}, {45.3627, 0.854538},
            {40.264, 0.70352}, {40.2201, 0.702222}, {40.2155, 0.650566}, {40.2254, -0.344136}, {40.2197, -0.296963},
            {40.175, -0.297411}, {40.1302, -0.297858}, {40.1253, -0.352886}, {40.1227, -0.380993},
            {40.0974, -0.393356}})};
  EXPECT_LT(DescribePlan(plan).room_overlap_m2, 1e-4);
}

TEST(PlanMetrics, KeysWithoutTruthLeaveTruthMetricsOut) {
  Case c;
  const auto keys = PlanEvalKeys(DescribePlan(c.plan), false);
  for (const auto& [k, v] : keys) EXPECT_NE(k, "room_iou_median");
  bool overlap = false;
  for (const auto& [k, v] : keys)
    if (k == "room_overlap_m2") overlap = v && std::abs(*v - 4.0) < 1e-9;
  EXPECT_TRUE(overlap);
}

}  // namespace
}  // namespace cogmap::eval
