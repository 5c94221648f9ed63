#pragma once
// Floor-plan metrics against a world's truth (issue 11, `cogmap eval` when the
// folder has plan.json). Everything in the world frame, metres.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cogmap/core/floor_plan.h"
#include "cogmap/plan/plan.h"

namespace cogmap::eval {

struct PlanMetricsOptions {
  double sample_step_m = 0.05;     // points sampled along plan and true walls
  double match_m = 0.3;            // a plan wall point matches a true wall this close ...
  double match_angle_deg = 20.0;   // ... running within this of its direction (duplication)
  double recall_within_m = 0.2;    // recall: a seeable true-wall point with a plan wall this close
  double sensor_range_m = 5.0;     // recall: seeable within this of the true path (eval::WallRecall)
  // Rooms: a true room whose box has world walls inside it (farther than
  // room_margin_m from its sides: a ring corridor's block, furniture) is the
  // part of the box reachable from the true path, in cells of room_cell_m.
  double room_cell_m = 0.1;
  double room_margin_m = 0.3;
};

struct PlanMetrics {
  int walls = 0, rooms = 0, doors = 0;
  double wall_length_m = 0.0;
  int64_t vertices = 0;
  double vertices_per_m = 0.0;            // plan wall vertices per metre of plan wall
  int64_t samples = 0;                    // plan wall points sampled
  std::optional<double> precision_p50_m;  // distance of plan wall points to the nearest true wall
  std::optional<double> precision_p95_m;
  double recall = 0.0;                    // as eval::WallRecall, on the plan walls
  double matched_plan_length_m = 0.0;     // plan wall length lying on (matching) true walls
  double covered_true_length_m = 0.0;     // true wall length with a matching plan wall on it
  std::optional<double> duplication;      // matched_plan_length_m / covered_true_length_m
  std::vector<double> room_iou;           // per true room (its reachable floor): IoU with its best plan room (0: none)
  std::optional<double> room_iou_median;
  // The same over the true rooms the true path enters (a point of it inside
  // the room's box): a robot that never entered a room cannot map it, and a
  // run that skips rooms (a simulated route whose waypoints were unreachable)
  // reads 0 for each in room_iou_median.
  std::vector<bool> room_entered;         // per true room
  int rooms_entered = 0;
  std::optional<double> room_iou_median_entered;
  double room_overlap_m2 = 0.0;           // total area where two plan rooms overlap
};

// Linear in the sizes of the plan and the world (grid indexes), except the
// recall's sight test, which is eval::WallRecall's.
// With 'room_labels' (rooms from a segmentation image; not empty), the room
// metrics are taken against them instead of truth.rooms: each labelled room
// (its whole floor) against the plan room covering most of it (IoU over the
// raster's cells, a cell counting as covered when its centre is inside the
// polygon); a room is entered when a true path point lies on its floor.
PlanMetrics EvaluatePlan(const plan::Plan& plan, const FloorPlan& truth, const std::vector<Vec2>& true_path,
                         const PlanMetricsOptions& options = {}, const RoomLabels* room_labels = nullptr);

// Metrics that need no truth (counts, vertices per metre, overlap).
PlanMetrics DescribePlan(const plan::Plan& plan);

// `cogmap eval --json` keys: plan_walls, plan_rooms, plan_doors,
// plan_vertices_per_m, plan_wall_precision_p50_m, plan_wall_precision_p95_m,
// plan_wall_recall, plan_duplication, room_iou_median, rooms_entered,
// room_iou_median_entered, room_overlap_m2 (nullopt: null, the metric is
// undefined).
std::vector<std::pair<std::string, std::optional<double>>> PlanEvalKeys(const PlanMetrics& m, bool with_truth);

}  // namespace cogmap::eval
