#pragma once
// The floor plan (docs/floor-plan.md) of a stored map, as `cogmap map` builds
// it into plan.json: for readers that have the store but not the folder's
// plan.json (the Python bindings, a map continued elsewhere).
#include "cogmap/asr/store.h"
#include "cogmap/plan/plan.h"

namespace cogmap::mapping {

// plan::BuildPlan over every ASR of 'store', with the store's room ids and
// each ASR's path as placed (asr::Placement::corrected_path), and the robot
// radius and sensor reach of its last run (asr::kMetaRobotRadius,
// asr::kMetaSensorReach; options' otherwise). Equals
// the plan.json that `cogmap map` wrote with the same store.
plan::Plan FloorPlanOfStore(const asr::AsrStore& store, const plan::PlanOptions& options = {});

// 'options' with the robot radius, sensor reach and beam of the store's last run
// (and the faces' offset from the wall surface that beam gives, when unset)
// where the store has them: what `cogmap map` and FloorPlanOfStore plan with.
plan::PlanOptions PlanOptionsOfStore(const asr::AsrStore& store, const plan::PlanOptions& options = {});

}  // namespace cogmap::mapping
