#pragma once
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/floor_plan.h"

namespace cogmap::asr {

// How an ASR is matched to a ground-truth room (issue 5, `cogmap eval`).
struct RoomMatchOptions {
  double cell_m = 0.1;         // the ASR's area: the cells its path sweeps, this size
  double majority = 0.5;       // matched when more than this share lies in one room
  bool prefer_true_path = true;  // use the ground-truth path when the ASR has one
};

struct RoomMetrics {
  int asr_count = 0;
  int room_count = 0;
  int matched_asrs = 0;   // ASRs that matched a room no earlier ASR matched
  int matched_rooms = 0;  // rooms matched by at least one ASR
  double room_precision = 0.0;  // matched_asrs / asr_count (0 when no ASR)
  double room_recall = 0.0;     // matched_rooms / room_count (0 when no room)
  std::vector<int> asr_room;    // per ASR (input order): the room index it lies in, or -1
};

// An ASR's area is the set of cell_m cells swept by the robot's path through it
// (its ground-truth path when the log has one, else its raw path carried into
// the corrected frame). Walls are not used: sonar sees through doorways, so an
// ASR's walls include pieces of the next room. The ASR lies in room r when more
// than 'majority' of those cells have their centre inside r's box. In id order,
// an ASR counts for precision when its room was not matched by an earlier ASR.
RoomMetrics EvaluateRooms(const std::vector<Asr>& asrs, const std::vector<NamedBox>& rooms,
                          const RoomMatchOptions& options = {});

// The same against rooms given as a raster (a room-segmentation image): a
// cell centre lies in the room whose label holds it.
RoomMetrics EvaluateRooms(const std::vector<Asr>& asrs, const RoomLabels& rooms, const RoomMatchOptions& options = {});

// How the store's room identities (revisits: ASRs given the room id of an
// earlier one, Placement::room_id) agree with the true rooms the ASRs lie in
// (RoomMetrics::asr_room, same order as 'room_ids'). A revisit is an ASR
// whose room id is not its own; it is right when it and the room's first
// ASR lie in the same true room, wrong when in two different ones, and
// unscored when either lies in no single room.
struct RevisitMetrics {
  int graph_rooms = 0;      // distinct room ids
  int revisits = 0;
  int revisits_right = 0;
  int revisits_wrong = 0;
};
RevisitMetrics EvaluateRevisits(const std::vector<int>& asr_ids, const std::vector<int>& room_ids,
                                const std::vector<int>& asr_room);

// The poses used for an ASR's area (see EvaluateRooms).
std::vector<Pose2> AreaPath(const Asr& asr, bool prefer_true_path = true);

}  // namespace cogmap::asr
