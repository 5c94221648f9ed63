// A helper of the suite until `cogmap map` writes plan.json itself (issue 11):
// builds the floor plan from a map folder's store (read only) and writes
// FOLDER/plan.json, so that `cogmap eval FOLDER --world W` scores it.
// Usage: cogmap_suite_plan_from_store FOLDER
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>

#include "cogmap/asr/store.h"
#include "cogmap/core/error.h"
#include "cogmap/io/atomic_file.h"
#include "cogmap/plan/plan.h"
#include "cogmap/plan/plan_json.h"

int main(int argc, char** argv) {
  using namespace cogmap;
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s MAP_FOLDER\n", argv[0]);
    return 2;
  }
  try {
    const std::filesystem::path dir(argv[1]);
    auto store = asr::SqliteAsrStore::Open((dir / "map.sqlite").string(), asr::SqliteAsrStore::OpenMode::kReadOnly);
    std::vector<asr::Asr> asrs;
    std::map<int, int> room_of;
    std::map<int, std::vector<Pose2>> placed;
    for (int id : store->Ids()) {
      auto a = store->Get(id);
      if (!a) continue;
      room_of[id] = store->RoomOf(id);
      if (auto p = store->GetPlacement(id)) placed[id] = p->corrected_path;
      asrs.push_back(std::move(*a));
    }
    const plan::Plan p = plan::BuildPlan(asrs, room_of, {}, placed);
    io::WriteFileAtomically((dir / "plan.json").string(), plan::PlanToJsonText(p));
    std::printf("%s: %zu walls, %zu rooms, %zu doors from %zu ASRs\n", (dir / "plan.json").c_str(), p.walls.size(),
                p.rooms.size(), p.doors.size(), asrs.size());
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
