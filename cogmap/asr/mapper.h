#pragma once
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "cogmap/asr/asr.h"
#include "cogmap/asr/boundary_detector.h"
#include "cogmap/asr/placement.h"
#include "cogmap/asr/store.h"
#include "cogmap/grid/range_fusion.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"
#include "cogmap/vectorize/vectorize.h"

namespace cogmap::asr {

// Options of the whole cognitive mapper (SPEC 2-4).
struct MapperOptions {
  double cell_m = 0.1;                 // the thesis's cell size (SPEC conventions)
  grid::MhimmOptions mhimm;            // per-ASR MHIMM grid (SPEC 2, §3.1.4)
  int grow_chunk_cells = 32;           // a room grid starts small and grows by this
  vectorize::VectorizeOptions vectorize;  // grid -> polylines (SPEC 3)
  BoundaryOptions boundary;            // where ASRs end (SPEC 4, fig. 3.4)
  double path_step_m = 0.05;           // the stored path keeps a pose every this far
  size_t max_replay_records = 4096;    // bound of the doorway replay buffer
  // The dominant orientation of each room's occupied cells (Asr::grid_orientation),
  // used by the heading correction's grid refinement (sonar robots only):
  // off, it is not computed.
  bool grid_orientation = true;
  // The floor each ASR saw (FreeSpaceHull) is taken through openings wider
  // than twice this: 0.5 m parts the floor at a door (0.8-1 m) and keeps a
  // 2 m corridor whole.
  double free_opening_m = 0.5;
  // ... and its convex hull simplified giving up at most this fraction of its
  // area (a grid's hull has a vertex every few cells: about 18 vertices
  // become 6-8).
  double free_hull_area_loss = 0.01;
  // Default mode, sonar robots: each room also has a grid that fuses every
  // echo over the sonar's cone (grid::MhimmOptions::cone_hits), and the walls
  // the ASR keeps (the map's, the floor plan's) are that grid's; the heading
  // correction and the pose graph work on the walls of the axis grid
  // (Asr::output_walls_local; docs/walls.md, "Sonar cone").
  bool cone_output_walls = false;
  // With cone_output_walls: the dominant orientation of the room's occupied
  // cells (Asr::grid_orientation, which the heading estimate and the pose
  // graph's wall-direction factor refine to) taken on the cone grid rather
  // than the axis grid. For rings that look only forward
  // (sensors::SeesOnlyForward; `cogmap map --cone-orientation`): on the axis
  // grid their walls lean with the direction of travel (docs/walls.md, "A
  // ring that looks only forward").
  bool orientation_from_cone = false;
  // ... where the two grids' orientations differ by at most this (modulo a
  // quarter turn): the most such a ring leans (up to 4.8 degrees on
  // nine_rooms without noise); beyond it the cone grid saw another room
  // shape, not the same walls placed better, and the axis grid's stays.
  double orientation_cone_window_rad = DegToRad(5.0);
  // Every hit of the room's grids tagged with the distance driven in the
  // ASR, and each wall vertex with the mean over the hits near it
  // (Asr::walls_seen_s): the pose graph bends the walls by the drift where
  // they were seen (default mode with the pose graph; nothing else reads them).
  bool seen_distances = false;
  // Each closed ASR is finished (vectorised on one thread; corrected, placed
  // and stored on another: the Worker in mapper.cc) while the next room's
  // records are fused on the caller's thread:
  // the same ASRs in the same order, the callback still on the caller's
  // thread (from a later Push or Finish). Ignored with an odometry filter,
  // whose corrections of the next records depend on the closed ASR.
  bool close_in_background = false;
};

// Continuing a run into an existing store (cogmap map --resume).
struct MapperResume {
  int next_id = 0;                 // the first new ASR's id (store MaxId() + 1)
  // Linked to the first new ASR: through 'leaving_exit' when the stored run
  // left it through a doorway (a run killed after a cut: the exit it was left
  // by, stored with it), else by a width-0 exit where the new log starts.
  std::optional<int> previous_asr;
  std::optional<Exit> leaving_exit;
  // Where the stored run ended (raw world frame): the new log's first odometry
  // pose is taken to be this pose, and every later one follows by dead reckoning.
  std::optional<Pose2> last_raw_pose;
};

// The rigid transform that best maps 'from' onto 'to' (same length, pose i
// with pose i): rotation = circular mean of the heading differences,
// translation matching the centroids. Identity for empty paths.
Pose2 BestRigidFit(const std::vector<Pose2>& from, const std::vector<Pose2>& to);

// The floor a room's grid saw (Asr::free_hull_local): the convex hull, in the
// grid's frame (metres), of the explored-empty cells (value below 0, the robot
// path included) reachable from the robot's path through openings wider than
// 2 x opening_m (a morphological opening of radius opening_m, city-block, seeded
// from the path): the floor seen through a door or a gap in a wall belongs to
// the space behind it. The hull is then simplified (SimplifyConvex) giving up
// at most max_area_loss of its area. Empty when the grid has no path cell.
std::vector<Vec2> FreeSpaceHull(const grid::Grid2D<float>& values, const vectorize::CellClasses& classes,
                                double opening_m, double max_area_loss = 0.0);

// A convex polygon with fewest vertices: drops, smallest first, the vertex
// whose triangle with its neighbours is the least area, while the area given
// up stays within max_area_loss (a fraction) of the polygon's. The result is
// convex and inside the polygon.
std::vector<Vec2> SimplifyConvex(std::vector<Vec2> poly, double max_area_loss);

// Run-state keys written with every ASR (so --resume can continue).
constexpr const char* kMetaLastRawPose = "last_raw_pose";  // "x y theta"
constexpr const char* kMetaNextId = "next_asr_id";
// The log those ASRs were mapped from (io::LogFingerprint; empty: standard
// input) and how many of its records the run had read when the last of them
// closed (its last_raw_pose is the pose of that record): `cogmap map --resume`
// given that log again continues from there instead of mapping it twice.
constexpr const char* kMetaLogFingerprint = "log_fingerprint";
constexpr const char* kMetaLastRecord = "last_record";
// The footprint radius (m) of the robot of the store's last run, shortest
// round-trip decimal: the floor plan's small-room size scales with it
// (plan::PlanOptions::robot_radius_m).
constexpr const char* kMetaRobotRadius = "robot_radius_m";
void SetRobotRadius(AsrStore* store, double radius_m);
// The stored radius; none when absent, an InputError naming the store when
// it is not a positive finite number (AsrStore::GetMetaPositive).
std::optional<double> RobotRadius(const AsrStore& store);
// How far from the robot the ASR grids of the store's last run took
// readings (m): the largest of min(max range, MHIMM window) over its
// sensors. Nothing in a grid lies farther from the path, so the floor plan's
// rooms reach no farther (plan::PlanOptions::reach_m). Same format.
constexpr const char* kMetaSensorReach = "sensor_reach_m";
void SetSensorReach(AsrStore* store, double reach_m);
std::optional<double> SensorReach(const AsrStore& store);
// The widest beam (full cone angle, rad) of the sensors of the store's last
// run: how far a wall's direction in an ASR may lean from one view to
// another (plan::PlanOptions::beam_width_rad). Same format.
constexpr const char* kMetaSensorBeam = "sensor_beam_rad";
void SetSensorBeam(AsrStore* store, double beam_rad);
std::optional<double> SensorBeam(const AsrStore& store);
// The largest ASR id of a run that finished (-1: none yet), written by
// mapping::MappingPipeline when it creates a store and at Finish(). ASRs after
// it were stored by a run that stopped before its end (a kill); absent in
// stores written before schema 3.
constexpr const char* kMetaFinishedThrough = "finished_through";
// The run-state values a resume continues from, as a run writes them
// (finished_through -1 or an ASR id, next_asr_id an ASR id, last_raw_pose a
// pose): none when absent, an InputError naming the store when the value is
// anything else (AsrStore::GetMetaInt, GetMetaPose).
std::optional<long> FinishedThrough(const AsrStore& store);
std::optional<long> NextAsrId(const AsrStore& store);
std::optional<Pose2> LastRawPose(const AsrStore& store);

struct MapperStats {
  int asr_count = 0;          // ASRs closed and handed to the callback
  long records = 0;
  long readings = 0;
  int turn_backs = 0;         // doorways the robot turned back in (no ASR)
  int64_t peak_grid_cells = 0; // largest room grid seen
  double seconds = 0.0;       // time spent inside Push / Finish (on the caller's thread)
};

// The cognitive mapper of SPEC 4 as a streaming API (fit for a robot): push
// every record in order; each ASR is mapped in its own MHIMM grid, sized to
// the room and grown as needed, and when the boundary detector cuts it, the
// grid is vectorised into walls, the ASR is built (walls in a local frame
// whose origin is the entry position and whose axes are the raw world's, so
// world_from_local_raw = (entry x, entry y, 0); see docs/store.md), handed to
// the corrector (heading correction, when set), stored in one transaction,
// passed to the callback, and its grid freed. Only the current room's grid
// and a short replay buffer (the current doorway's readings) are held.
class CognitiveMapper {
 public:
  using Callback = std::function<void(const Asr&)>;
  // Heading correction of a closed ASR (localize::HeadingCorrector::Close).
  using Corrector = std::function<Asr(Asr)>;

  // 'store' may be null (then ASRs only go to the callback).
  CognitiveMapper(const sensors::RobotDescription& robot, const MapperOptions& options,
                  AsrStore* store, Callback on_close = {});
  ~CognitiveMapper();

  void SetCorrector(Corrector corrector) { corrector_ = std::move(corrector); }
  // Odometry pre-correction (localize::DriftHeadingCorrector::CorrectOdometry,
  // default mode): maps each raw odometry pose (raw world frame) and its time to
  // the pose that the grids, the boundary detector and the corrector use. When
  // set, each ASR is built and handed to the corrector in that pre-corrected
  // frame; afterwards its raw fields (world_from_local_raw, entry pivot, exits,
  // path) are re-expressed in the raw odometry frame by the rigid transform that
  // best maps its pre-corrected path onto the raw one (BestRigidFit), so the
  // store keeps the odometry as it was and heading_correction_rad is
  // corrected - raw. Before the first Push.
  using OdometryFilter = std::function<Pose2(const Pose2& raw_odom, double time_s)>;
  void SetOdometryFilter(OdometryFilter filter) { odometry_filter_ = std::move(filter); }
  // Placement of a closed ASR (graph::MapOptimizer::Place, default mode):
  // sets world_from_local_corrected. Runs after the corrector, before the raw
  // fields are re-expressed in the raw odometry frame: it sees the ASR in the
  // frame its walls were built in (pre-corrected when filtered).
  void SetPlacer(Corrector placer) {
    placer_ = [placer = std::move(placer)](Asr a, std::unique_ptr<PlacementWork>) { return placer(std::move(a)); };
    preparer_ = {};
  }
  // The same in two parts: 'prepare' reads the closed ASR alone (its
  // walls, path and grid orientation as vectorised) and may run on another
  // thread while the ASR before it is placed: with close_in_background, on
  // the walls stage's thread, which has less to do than the placing stage
  // when the pose graph places. 'place' gets its result (null when it was
  // not made ahead: with a corrector, which changes the ASR in between).
  using Preparer = std::function<std::unique_ptr<PlacementWork>(const Asr&)>;
  using Placer = std::function<Asr(Asr, std::unique_ptr<PlacementWork>)>;
  void SetPlacer(Preparer prepare, Placer place) {
    preparer_ = std::move(prepare);
    placer_ = std::move(place);
  }
  // Drift removed while each room is mapped (default mode with the pose
  // graph; not with an odometry filter): when ASR k starts, the mapper waits
  // until ASR k - lag is placed and stored, then builds k's grids on the
  // odometry re-integrated from k's entry under rate_after(k - lag) rad per
  // metre (each step turned by -rate x the distance driven before it, as
  // CorrectedPath does), and records that rate in Asr::pre_bend_rad_per_m.
  // The path it keeps stays raw. With the rate of an ASR 'lag' back, the
  // rooms come out the same with the placing done on another thread or not.
  // lag 0: a rate known before the run (the second pass of `cogmap map`,
  // mapping::MappingOptions::remove_drift_rad_per_m), asked with the room's
  // own id and waiting for nothing: every room, the first included, is bent.
  // Before the first Push.
  using PreBend = std::function<double(int placed_id)>;
  void SetPreBend(int lag, PreBend rate_after) {
    pre_bend_lag_ = std::max(0, lag);
    pre_bend_ = std::move(rate_after);
  }
  // Before the first Push.
  void Resume(const MapperResume& resume);
  // The log being mapped (io::LogFingerprint) and how many of its records
  // come before the first one pushed (skipped by a resumed run): written with
  // every ASR (kMetaLogFingerprint, kMetaLastRecord). Before the first Push.
  void SetLogIdentity(std::string fingerprint, long first_record) {
    log_fingerprint_ = std::move(fingerprint);
    first_record_ = first_record;
  }

  void Push(const sensors::LogRecord& record);
  // Closes the ASR being mapped (a log that ends mid-room). Idempotent.
  void Finish();
  // Waits until every room closed so far is placed and stored, and hands
  // each to the callback (MapperOptions::close_in_background; nothing to wait
  // for without it): the store then holds exactly the rooms the callbacks
  // have seen, for outputs written in the middle of a run.
  void Settle() { DeliverFinished(true); }

  const MapperStats& stats() const { return stats_; }
  const BoundaryDetector& detector() const { return detector_; }
  // The id of the ASR being mapped (-1 before the first record / after Finish).
  int current_id() const { return current_ ? current_->asr.id : -1; }
  // Cells of the current room grid (0 when none).
  int64_t current_grid_cells() const;
  // The grid of the room being mapped, in its local frame (nullptr when none),
  // and where that frame lies in the raw odometry frame.
  const grid::HimmFusion* current_grid() const { return current_ ? current_->grid.get() : nullptr; }
  Pose2 current_world_from_local() const { return current_ ? current_->local_from_world.inverse() : Pose2{}; }

 private:
  struct Current {
    Asr asr;
    std::unique_ptr<grid::HimmFusion> grid;
    std::unique_ptr<grid::HimmFusion> cone_grid;  // MapperOptions::cone_output_walls
    std::vector<double> path_times;
    std::vector<Pose2> raw_path;  // the raw odometry at the poses of asr.path
    std::vector<double> true_path_times;
    Pose2 local_from_world;
    // The pre-bend's re-integration (Asr::pre_bend_rad_per_m removed), from
    // the local origin: set in Start.
    DriftReintegration bend{0.0, Vec2(0.0, 0.0)};
    // The distance along asr.path to its last pose (the grids' hits are
    // tagged with it plus the way from there: HimmFusion::SetDistance).
    double path_s = 0.0;
    // The turn summed since the last path pose (Asr::path_turn_rad).
    double turn_acc = 0.0, turn_last = 0.0;
    bool turn_started = false;
    // The records of the log read when it closed (kMetaLastRecord).
    long records_through = 0;
  };
  struct Buffered {
    long seq;
    sensors::LogRecord record;  // odometry in the raw world frame (pre-corrected when filtered)
    Pose2 raw_odom;             // raw world frame
  };
  void Start(const Pose2& entry_pose, double time_s, const std::optional<Exit>& entry_exit);
  void Feed(const sensors::LogRecord& record, const Pose2& raw_odom);
  void Close(const std::optional<Exit>& exit, double end_time_s);
  // The closed ASR's walls (its grid vectorised and freed), then the walls
  // it keeps (the cone grid's), its correction, placement and store entry
  // (MapperOptions::close_in_background: each on a thread of the Worker),
  // then its hand-over to the callback (on the caller's thread).
  void BuildWalls(Current& closing);
  // The placer's part made from the closed ASR alone, ahead (null: none).
  std::unique_ptr<PlacementWork> Prepare(const Current& closing) const;
  Asr Place(std::unique_ptr<Current> closing, const Pose2& last_raw_pose, int next_id,
            std::unique_ptr<PlacementWork> prepared);
  void Deliver(const Asr& out);
  // Hands over the ASRs the worker has finished; with 'all', waits for every one.
  void DeliverFinished(bool all);
  class Worker;
  std::unique_ptr<Worker> worker_;

  sensors::RobotDescription robot_;
  MapperOptions options_;
  AsrStore* store_;
  Callback on_close_;
  Corrector corrector_;
  Preparer preparer_;
  Placer placer_;
  OdometryFilter odometry_filter_;
  PreBend pre_bend_;
  int pre_bend_lag_ = 2;
  BoundaryDetector detector_;
  std::unique_ptr<Current> current_;
  bool seen_truth_ = false;  // the log has ground truth: sample paths only at records with it
  std::deque<Buffered> buffer_;
  long seq_ = 0;
  int next_id_ = 0;
  MapperResume resume_;
  bool resumed_ = false;
  std::optional<Pose2> world_from_odom_;
  Pose2 last_raw_pose_;
  std::string log_fingerprint_;
  long first_record_ = 0;
  bool finished_ = false;
  MapperStats stats_;
};

}  // namespace cogmap::asr
