#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "cogmap/core/geometry.h"

namespace cogmap::asr {

// A doorway or corridor cut through which the robot left one ASR for another
// (SPEC 4). World frame of the raw (odometry) map.
struct Exit {
  Vec2 center_m{0, 0};
  double width_m = 0.0;
  int from_asr = -1;
  int to_asr = -1;  // -1 while the robot has not entered the next ASR yet
};

// Bytes of the three representations of table 4.2.
struct StageBytes {
  int64_t grid = 0;       // the ASR's MHIMM grid, one byte per cell
  int64_t vertices = 0;   // extracted points, 2 x int16 per vertex
  int64_t polylines = 0;  // final polylines, compact binary encoding
};

// Seconds spent per stage when the ASR closed.
struct StageSeconds {
  double grid = 0.0;  // fusing readings (accumulated while mapping)
  double clean = 0.0;
  double extract = 0.0;
  double simplify = 0.0;  // vertex simplify + Douglas-Peucker
  double fit = 0.0;
  double total() const { return grid + clean + extract + simplify + fit; }
};

// The dominant orientation of an ASR's occupied grid cells (a projection
// profile, vectorize::DominantOrientation), in the local frame, folded into
// [-45, 45) degrees. Computed when the ASR closes, while its grid exists; the
// default heading correction refines the EM direction with it. Stored from
// schema 3 on (a resumed pose graph replays it).
struct GridOrientation {
  bool valid = false;
  double angle_rad = 0.0;
  double contrast = 0.0;  // peak / median profile score (about 1: no orientation)
  int cells = 0;
};

// An Absolute Space Representation: one room or stretch of corridor (SPEC 4).
struct Asr {
  int id = -1;
  // Pose of the ASR's local frame in the world: raw from odometry, and after
  // heading correction (SPEC 5). The walls are stored in the local frame.
  Pose2 world_from_local_raw;
  Pose2 world_from_local_corrected;
  Vec2 entry_pivot_m{0, 0};               // where the robot entered (world, raw)
  std::vector<Polyline> walls_local;      // in the local frame
  std::vector<Exit> exits;                // exits through which it was left/entered
  std::vector<Pose2> path;                // robot poses through it (world, raw)
  // Per pose of 'path': how far the heading turned (summed absolute turns)
  // since the previous pose, the first 0. A turn on the spot moves the robot
  // no distance and falls between two poses. Stored from schema 7 on (the
  // pose graph's odometry noise grows with it: a resumed run replays a killed
  // run's ASRs with it); empty for ASRs of older stores.
  std::vector<double> path_turn_rad;
  double turn_after_path_rad = 0.0;       // summed turn from the last path pose to the ASR's end
  // The floor the sensors saw: the convex hull (local frame, counter-
  // clockwise) of the grid's explored-empty cells connected to the robot's
  // path, simplified to a few vertices (FreeSpaceHull). The floor plan lets the room reach this far even where no wall
  // bounds it (a room the robot only looked into). Empty: not known (a store
  // older than schema 4).
  std::vector<Vec2> free_hull_local;
  std::vector<Pose2> true_path;           // ground-truth poses, when the log has them
  double start_time_s = 0.0;
  double end_time_s = 0.0;
  StageBytes bytes;
  StageSeconds seconds;
  double heading_correction_rad = 0.0;    // rotation applied (corrected - raw)
  double heading_uncertainty_rad = -1.0;  // < 0: not estimated
  GridOrientation grid_orientation;       // transient, see GridOrientation
  // Transient (MapperOptions::cone_output_walls): the walls of the room's
  // cone grid, which replace walls_local once the ASR is placed; the pose
  // graph registers and closes loops on walls_local as mapped.
  bool has_output_walls = false;
  std::vector<Polyline> output_walls_local;
  // The walls the pose graph matched when they are not walls_local (then
  // walls_local are the cone grid's): stored (schema 5) so that a resumed
  // run matches what the uninterrupted run matched.
  bool has_matched_walls = false;
  std::vector<Polyline> matched_walls_local;
  // Transient: per vertex of walls_local (and of output_walls_local) the
  // distance the robot had driven in the ASR when the echoes there were
  // heard, the mean over the grid's hits within two cells (NaN: none); the
  // pose graph bends each vertex by the drift at that distance. Empty: not
  // known (then the nearest path pose stands in).
  std::vector<std::vector<double>> walls_seen_s;
  std::vector<std::vector<double>> output_walls_seen_s;
  // The drift rate (rad per metre) removed inside the ASR while its grids were
  // built (default mode, asr::CognitiveMapper::SetPreBend): each odometry step
  // re-integrated from the ASR's entry turned by -rate x the distance driven,
  // as CorrectedPath does. Its walls (as mapped) and free-space hull are in
  // that bent frame; 'path' stays the raw odometry. 0: mapped on the raw
  // odometry. Stored from schema 6 on.
  double pre_bend_rad_per_m = 0.0;

  std::vector<Polyline> WallsWorldRaw() const { return Transform(world_from_local_raw, walls_local); }
  std::vector<Polyline> WallsWorldCorrected() const {
    return Transform(world_from_local_corrected, walls_local);
  }
};

// A stored ASR as the pose graph first saw it: its matched walls as
// walls_local and the walls it keeps as output_walls_local (when the two
// differ; else unchanged). For replaying a run into the graph (--resume).
inline Asr MatchedView(Asr a) {
  if (!a.has_matched_walls) return a;
  a.output_walls_local = std::move(a.walls_local);
  a.has_output_walls = true;
  a.walls_local = std::move(a.matched_walls_local);
  a.matched_walls_local = {};
  a.has_matched_walls = false;
  return a;
}

// The robot's path through an ASR as the pose graph places it: the raw path
// in the ASR's local frame (world_from_local_raw^-1), re-integrated with the
// odometry's heading drift removed (each step turned by -rate x the distance
// driven from the ASR's origin to the step's middle, each heading by -rate x
// the distance to it), then placed by world_from_local_corrected. With rate 0
// this is world_from_local_corrected * world_from_local_raw^-1 * path.
std::vector<Pose2> CorrectedPath(const Asr& asr, double drift_rate_rad_per_m);
// The same for a path and the two placements given apart from an Asr.
std::vector<Pose2> CorrectedPath(const std::vector<Pose2>& path, const Pose2& world_from_local_raw,
                                 const Pose2& world_from_local_corrected, double drift_rate_rad_per_m);

}  // namespace cogmap::asr
