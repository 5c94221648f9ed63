#include "cogmap/asr/room_metrics.h"

#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace cogmap::asr {

std::vector<Pose2> AreaPath(const Asr& asr, bool prefer_true_path) {
  if (prefer_true_path && !asr.true_path.empty()) return asr.true_path;
  const Pose2 corr = asr.world_from_local_corrected * asr.world_from_local_raw.inverse();
  std::vector<Pose2> out;
  out.reserve(asr.path.size());
  for (const auto& p : asr.path) out.push_back(corr * p);
  return out;
}

namespace {

// rooms_of(c, counts) adds one to counts[r] for every room r holding the point c.
template <class RoomsOf>
RoomMetrics Evaluate(const std::vector<Asr>& asrs, size_t room_count, RoomsOf rooms_of,
                     const RoomMatchOptions& options) {
  RoomMetrics m;
  m.asr_count = static_cast<int>(asrs.size());
  m.room_count = static_cast<int>(room_count);
  std::vector<bool> room_taken(room_count, false);
  for (const Asr& a : asrs) {
    std::set<std::pair<long, long>> cells;
    for (const auto& p : AreaPath(a, options.prefer_true_path))
      cells.insert({static_cast<long>(std::floor(p.x / options.cell_m)),
                    static_cast<long>(std::floor(p.y / options.cell_m))});
    int best = -1;
    if (!cells.empty()) {
      std::vector<int> counts(room_count, 0);
      for (const auto& [cx, cy] : cells) rooms_of(Vec2((cx + 0.5) * options.cell_m, (cy + 0.5) * options.cell_m), &counts);
      for (size_t r = 0; r < room_count; ++r)
        if (counts[r] > options.majority * static_cast<double>(cells.size()) &&
            (best < 0 || counts[r] > counts[best]))
          best = static_cast<int>(r);
    }
    m.asr_room.push_back(best);
    if (best >= 0 && !room_taken[best]) {
      room_taken[best] = true;
      ++m.matched_asrs;
    }
  }
  for (bool t : room_taken) m.matched_rooms += t ? 1 : 0;
  m.room_precision = m.asr_count ? static_cast<double>(m.matched_asrs) / m.asr_count : 0.0;
  m.room_recall = m.room_count ? static_cast<double>(m.matched_rooms) / m.room_count : 0.0;
  return m;
}

}  // namespace

RoomMetrics EvaluateRooms(const std::vector<Asr>& asrs, const std::vector<NamedBox>& rooms,
                          const RoomMatchOptions& options) {
  return Evaluate(asrs, rooms.size(), [&](const Vec2& c, std::vector<int>* counts) {
    for (size_t r = 0; r < rooms.size(); ++r)
      if (rooms[r].Contains(c)) ++(*counts)[r];
  }, options);
}

RoomMetrics EvaluateRooms(const std::vector<Asr>& asrs, const RoomLabels& rooms, const RoomMatchOptions& options) {
  return Evaluate(asrs, rooms.names.size(), [&](const Vec2& c, std::vector<int>* counts) {
    const int r = rooms.At(c);
    if (r >= 0) ++(*counts)[r];
  }, options);
}

RevisitMetrics EvaluateRevisits(const std::vector<int>& asr_ids, const std::vector<int>& room_ids,
                                const std::vector<int>& asr_room) {
  RevisitMetrics m;
  std::map<int, int> true_room_of_id;
  for (size_t i = 0; i < asr_ids.size() && i < asr_room.size(); ++i) true_room_of_id[asr_ids[i]] = asr_room[i];
  std::set<int> rooms(room_ids.begin(), room_ids.end());
  m.graph_rooms = static_cast<int>(rooms.size());
  for (size_t i = 0; i < asr_ids.size() && i < room_ids.size(); ++i) {
    if (room_ids[i] == asr_ids[i]) continue;
    ++m.revisits;
    auto first = true_room_of_id.find(room_ids[i]);
    const int here = i < asr_room.size() ? asr_room[i] : -1;
    if (first == true_room_of_id.end() || first->second < 0 || here < 0) continue;
    if (first->second == here) ++m.revisits_right; else ++m.revisits_wrong;
  }
  return m;
}

}  // namespace cogmap::asr
