#include "cogmap/mapping/floor_plan.h"

#include <map>
#include <vector>

#include "cogmap/asr/mapper.h"

namespace cogmap::mapping {

plan::PlanOptions PlanOptionsOfStore(const asr::AsrStore& store, const plan::PlanOptions& options) {
  plan::PlanOptions o = options;
  if (const auto r = asr::RobotRadius(store)) o.robot_radius_m = *r;
  if (const auto r = asr::SensorReach(store)) o.reach_m = *r;
  if (const auto b = asr::SensorBeam(store)) o.beam_width_rad = *b;
  // The faces' offset from the wall's surface, by the beam, when the caller
  // left it unset (plan::FaceBehindForBeam).
  if (o.face_behind_m == 0.0) o.face_behind_m = plan::FaceBehindForBeam(o.beam_width_rad, o.reach_m, o.cell_m);
  return o;
}

plan::Plan FloorPlanOfStore(const asr::AsrStore& store, const plan::PlanOptions& options) {
  const plan::PlanOptions o = PlanOptionsOfStore(store, options);
  std::vector<asr::Asr> all;
  std::map<int, int> room_of;
  std::map<int, std::vector<Pose2>> placed_paths;
  for (int id : store.Ids()) {
    if (auto x = store.Get(id)) all.push_back(std::move(*x));
    room_of[id] = store.RoomOf(id);
    if (auto p = store.GetPlacement(id)) placed_paths[id] = std::move(p->corrected_path);
  }
  return plan::BuildPlanReleasing(&all, room_of, o, &placed_paths);  // nothing else reads them
}

}  // namespace cogmap::mapping
