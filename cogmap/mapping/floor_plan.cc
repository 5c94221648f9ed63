#include "cogmap/mapping/floor_plan.h"

#include <map>
#include <vector>

namespace cogmap::mapping {

plan::Plan FloorPlanOfStore(const asr::AsrStore& store, const plan::PlanOptions& options) {
  std::vector<asr::Asr> all;
  std::map<int, int> room_of;
  std::map<int, std::vector<Pose2>> placed_paths;
  for (int id : store.Ids()) {
    if (auto x = store.Get(id)) all.push_back(std::move(*x));
    room_of[id] = store.RoomOf(id);
    if (auto p = store.GetPlacement(id)) placed_paths[id] = std::move(p->corrected_path);
  }
  return plan::BuildPlanReleasing(&all, room_of, options, &placed_paths);  // nothing else reads them
}

}  // namespace cogmap::mapping
