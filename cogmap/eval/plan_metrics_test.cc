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
  EXPECT_NEAR(m.room_overlap_m2, 4.0, 1e-9);
  // Recall: 12 of 16 m, plus the top wall's 0.2 m next to each side wall.
  EXPECT_GT(m.recall, 12.0 / 16.0);
  EXPECT_LT(m.recall, 12.5 / 16.0);
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
