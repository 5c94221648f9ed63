#include "cogmap/mapping/floor_plan.h"

#include <charconv>
#include <cmath>
#include <map>
#include <vector>

#include "cogmap/asr/mapper.h"

namespace cogmap::mapping {

plan::Plan FloorPlanOfStore(const asr::AsrStore& store, const plan::PlanOptions& options) {
  plan::PlanOptions o = options;
  if (const auto r = store.GetMeta(asr::kMetaRobotRadius)) {
    double v = 0.0;
    const auto [end, ec] = std::from_chars(r->data(), r->data() + r->size(), v);
    if (ec == std::errc() && end == r->data() + r->size() && std::isfinite(v) && v > 0.0) o.robot_radius_m = v;
  }
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
