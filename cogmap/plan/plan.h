#pragma once
// The floor plan (issue 11): one wall per physical wall face, rooms as
// non-overlapping polygons, doors as gaps, and the room graph through them.
// Made from the placed ASRs (the pose graph's poses) and the store's room ids.
// Everything is in the map frame: metres, x east, y north (the raw odometry
// frame of the first run, as placed by the correction).
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/core/geometry.h"
#include "cogmap/core/pose2.h"

namespace cogmap::plan {

// One wall face: the evidence of every ASR that saw this face, fused.
struct Wall {
  Polyline points;            // >= 2 distinct points, map frame
  bool free_on_left = true;   // free space lies left of the direction first -> last point
  double weight = 0.0;        // evidence behind it (metres of wall seen, weighted by quality)
  std::vector<int> asr_ids;   // the ASRs whose walls were fused into it
  bool squared = false;       // snapped to one of the building's dominant directions
  // A thin wall seen from both sides (its two faces closer than
  // PlanOptions::thin_wall_m): free space on both sides, drawn once.
  bool two_sided = false;
};

// An exit the robot passed, as a gap in the walls.
struct Door {
  int id = -1;
  Vec2 a{0, 0}, b{0, 0};      // the gap's ends (the jambs), map frame
  int room_a = -1;            // plan room on each side (-1: none)
  int room_b = -1;
  int from_asr = -1;          // the exit's ASRs (asr::Exit)
  int to_asr = -1;
  Vec2 center() const { return 0.5 * (a + b); }
  double width_m() const { return (b - a).norm(); }
};

// A room (or a whole corridor) of the plan.
struct Room {
  int id = -1;
  std::string name;              // "Room 3", "Corridor 1"
  bool corridor = false;
  std::vector<Vec2> polygon;     // counter-clockwise, simple, first point not repeated
  double area_m2 = 0.0;
  Vec2 label{0, 0};              // a point inside the polygon for its label
  std::vector<int> doors;        // Door ids
  std::vector<int> asr_ids;      // ASRs drawn as this room
  std::vector<int> graph_rooms;  // store room ids (asr::SqliteAsrStore::RoomOf) it shows
};

// The room graph: plan rooms joined through a door.
struct Edge {
  int room_a = -1;
  int room_b = -1;
  int door = -1;
};

struct Plan {
  std::vector<Wall> walls;
  std::vector<Room> rooms;
  std::vector<Door> doors;
  std::vector<Edge> edges;
  std::optional<Pose2> home;  // the robot's first pose
  Vec2 min{0, 0}, max{0, 0};  // bounds of walls and rooms
  double dominant_direction_rad = 0.0;  // the building's wall direction, modulo a quarter turn, in [0, pi/2)
  double direction_scatter_rad = 0.0;   // wall-direction scatter the squaring test allowed for (BuildPlan)
};

// How far behind a wall's surface a sensor's fitted faces lie (metres;
// negative: in front), by its beam: a cone wider than a cell at the reach
// (a sonar; grid::MhimmOptions::cone_hits' test) returns the nearest echo in
// it and its faces lie in front, 0.025 m; a ray's (a laser's) hits mark
// their cell and its neighbours, the band's middle is kept, and its faces
// lie 0.03 m behind. Measured with simulated 16-sonar and laser runs on
// walls of known place, medians per run: sonar -0.009 to -0.041, laser
// +0.012 to +0.050 (docs/floor-plan.md, walls step 8).
double FaceBehindForBeam(double beam_rad, double reach_m, double cell_m);

// How BuildPlan fuses walls and cuts rooms (docs/floor-plan.md).
struct PlanOptions {
  // Walls: the ASRs' wall segments, each with the side the robot saw it from
  // (graph::FaceWalls), are grouped into faces and each face fitted as one line.
  double min_segment_m = 0.2;          // shorter ASR wall segments are not evidence (chamfers, sonar notches)
  double same_face_m = 0.3;            // a segment joins a face when both its ends lie this close to its line
  double face_angle_deg = 20.0;        // ... its free-side normal agrees this well
  double join_gap_m = 0.4;             // ... and it lies within this of the face's extent along it
  double min_wall_m = 0.4;             // fused faces shorter than this are dropped (notches)
  double thin_wall_m = 0.15;           // opposite faces of a wall thinner than this (or crossed by less than same_face_m) are one thin wall seen from both sides
  // Where a sensor's fitted wall faces lie against the wall's surface,
  // metres behind it (negative: in front of it): two faces of one wall t
  // thick are seen t - 2 face_behind_m apart, and are one thin wall when
  // that is under thin_wall_m - 2 face_behind_m. `cogmap map` sets it from
  // the robot's beam (FaceBehindForBeam); 0: faces on the surface.
  double face_behind_m = 0.0;
  double residual_floor_m = 0.03;      // floor of a face's fit residual (1 sigma)
  double correlation_length_m = 0.5;   // residuals along a wall are correlated over this (one independent error)
  double heading_floor_deg = 1.0;      // model error of a wall's direction (ASR heading), added to its fit error
  double square_z = 2.576;             // squared when within this many sigma of a dominant direction (99 %)
  double corner_m = 0.6;               // two wall ends this close to their lines' crossing are joined there
  double corner_min_angle_deg = 30.0;  // ... when the walls differ in direction by at least this
  double chamfer_max_m = 0.9;          // a diagonal wall this short between two walls' ends is a chamfer ...
  double chamfer_end_m = 0.35;         // ... when its ends lie this close to theirs: removed, the corner closed
                                       // (longer ones when the beam explains them: beam_width_rad)
  // Doors: each exit (asr::Exit) is a gap in the walls near it.
  double door_search_m = 0.8;          // the exit's centre within this of a wall line
  double wall_thickness_m = 0.4;       // faces within this of the door line are cut
  // A door (not between jambs) farther than this from the border its two
  // rooms share moves onto that border, where the robot's way crossed it
  // (docs/floor-plan.md, "Room graph").
  double door_border_m = 0.4;
  double min_door_m = 0.5;             // door widths are clamped into [min, max]
  double max_door_m = 2.5;
  // Rooms: a flood fill of a grid from each room's path, walls and doors blocking.
  double cell_m = 0.1;
  // Room outlines are traced on a lattice of half cells square to the
  // dominant direction; each stretch of an outline between the corners where
  // three rooms (or none) meet is then straightened within this many cells
  // (Douglas-Peucker), alike for the two rooms either side: a border turned
  // against the lattice (a wing at 30 degrees) is a straight line, not the
  // cells' staircase (which strays from the line by up to a cell). 0: as
  // traced.
  double outline_tolerance_cells = 1.0;
  double max_cells = 3.0e7;            // the cell grows beyond cell_m when the map would need more
  double seed_door_clearance_m = 0.8;  // path poses this close to an exit do not seed its room
  double corridor_max_width_m = 3.0;   // a corridor piece: at most this wide ...
  double corridor_min_aspect = 2.0;    // ... and at least this many times longer than wide
  // Two corridor pieces are joined through an exit, or where their regions
  // meet (directly or across at most this much unclaimed floor) along at
  // least this much border: the robot leaves a corridor piece into a room
  // and comes back out into the next piece, so the pieces of one corridor
  // often share no exit.
  double corridor_touch_m = 1.0;
  // A chain of corridor pieces met end to end along open floor (a corridor
  // left into a room every few metres: docs/floor-plan.md) whose pieces are
  // wider than corridor_max_width_m may be up to this wide while each join
  // widens the wider of its two chains by at most corridor_chain_slack (a
  // fraction): the corridors of hospitals and schools (2.4-3.6 m and more)
  // are cut into pieces as wide as they are, and end to end those stay that
  // wide, while a room beside a corridor widens it by its depth. Such a
  // chain is a corridor when twice corridor_min_aspect times longer than
  // wide (two offices side by side whose wall was missed are a short wide
  // chain).
  double corridor_chain_max_width_m = 4.0;
  double corridor_chain_slack = 0.15;
  // A piece that is not a corridor piece but meets two corridor pieces that
  // turn (axes more than 45 degrees apart), with at most this many times
  // their floor per metre of the robot's path, is a corner of the corridor
  // (an L reads as wide; docs/floor-plan.md).
  double corner_floor_ratio = 1.5;
  // Two rooms (neither a corridor) whose regions meet across open floor (no
  // wall, no door line) along more than this are one space of the plan: a
  // room's border is walls and doors, and no doorway is wider than
  // max_door_m. The room graph keeps both (the robot cut an open-plan room
  // where clutter narrowed it).
  double open_border_m = 2.5;
  double sliver_path_m = 0.5;          // a store room with less path than this is absorbed by a neighbour
  // A plan room whose floor, once the rooms have split the free space, is
  // smaller than a square of small_room_radii robot radii on a side (three
  // robot diameters: 2.4 m2 for a Pioneer, 0.36 m2 for an EV3 rover) joins
  // the neighbour it meets along the most border (through a door line or
  // open floor, never through a wall): a space the robot drove into and out
  // of holds its turn, so the piece is what was left of a room or corridor
  // between its neighbours' floods. The room graph keeps it. 0: off.
  double small_room_radii = 6.0;
  double robot_radius_m = 0.26;        // the robot's footprint radius (sensors::RobotDescription)
  // The rooms split the floor the robot's centre can reach (farther than
  // robot_radius_m from every wall), then each fills the cells beside its
  // walls next to its own floor: a room does not spread through a gap in
  // its walls narrower than the robot (docs/floor-plan.md, "Rooms"). False:
  // every free cell floods alike.
  bool gap_closing = true;
  // A room floods at most this far (geodesic, 4-connected steps, so up to
  // sqrt(2) times it across) from its path: its ASR grids took no reading
  // farther (`cogmap map` sets the robot's sensor reach, min(max range,
  // MHIMM window); asr::kMetaSensorReach). 0: no bound but the hulls.
  double reach_m = 0.0;
  double min_room_area_m2 = 0.25;      // smaller rooms are dropped
  // Walls: two faces that face away from each other and cross (an X) are
  // one wall seen tilted from both sides when they differ in direction by
  // no more than each can lean, atan(reach_m sin(beam / 2) / its length),
  // both together (without reach_m: the beam itself). `cogmap map` sets
  // the widest beam of the robot, asr::kMetaSensorBeam: 30 degrees for a
  // Polaroid sonar, a fraction of a degree for a laser. 0: never.
  // The same beam rounds a concave corner seen from d metres with a radius
  // up to 2 cells + tan(beam / 2) d: a diagonal that is that corner's chord
  // is dropped and the corner closed (docs/floor-plan.md, walls step 9).
  double beam_width_rad = 0.0;
  // The rooms' outlines are filled and traced on this many threads (at most
  // 2; the same outlines: each fill reads the labels its room has, each
  // trace the finished labels alone). `cogmap map` sets its --threads.
  int threads = 1;
};

// The floor plan of placed ASRs (world_from_local_corrected, walls_local).
// 'room_of_asr': the store's room ids (asr::SqliteAsrStore::RoomOf; revisits
// share one; missing ASRs are their own room). 'placed_paths': the robot's path
// through each ASR as placed (asr::Placement::corrected_path); an ASR missing
// there uses its raw path carried by its placement (no drift inside it).
Plan BuildPlan(const std::vector<asr::Asr>& asrs, const std::map<int, int>& room_of_asr,
               const PlanOptions& options = {},
               const std::map<int, std::vector<Pose2>>& placed_paths = {});
// The same plan; each ASR's walls, paths and floor, and the placed paths, are
// released (emptied) as soon as they are read, before the plan floods its
// rooms, so they do not add to the plan's peak memory. Ids, poses, exits,
// times and sizes stay. For a caller that has no further use for them.
Plan BuildPlanReleasing(std::vector<asr::Asr>* asrs, const std::map<int, int>& room_of_asr, const PlanOptions& options,
                        std::map<int, std::vector<Pose2>>* placed_paths);

// The plan carried by 'pose' (for example walls.json's world_from_map, to
// compare it with a world): every point, the home pose and the bounds.
Plan TransformPlan(const Pose2& pose, const Plan& plan);

}  // namespace cogmap::plan
