#pragma once
// The whole mapping pipeline as one streaming API (issue 13): records in, ASRs
// out as they close, the corrected map at the end. `cogmap map`, the Python
// bindings and the ROS node all map through it. Memory is bounded by the open
// room (the mapper) plus what the pose graph keeps per ASR (its walls).
//
//   mapping::MappingPipeline p(robot, options, store.get());
//   p.OnAsrClosed([](const mapping::AsrSummary& s) { ... });
//   while (log->Next(&rec)) p.Push(rec);
//   const mapping::RunResult& r = p.Finish();   // placements written to the store
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cogmap/asr/mapper.h"
#include "cogmap/asr/store.h"
#include "cogmap/core/pose2.h"
#include "cogmap/graph/map_optimizer.h"
#include "cogmap/localize/heading_corrector.h"
#include "cogmap/localize/odometry_corrector.h"
#include "cogmap/localize/odometry_scale.h"
#include "cogmap/localize/scan_odometry.h"
#include "cogmap/sensors/reading.h"
#include "cogmap/sensors/robot.h"

namespace cogmap::mapping {

// How ASRs are placed in the map (docs/pose-graph.md, docs/heading-correction.md).
enum class Correction {
  kPoseGraph,    // default mode: the pose graph over ASRs
  kDriftFilter,  // default mode without the graph: drift filter + EM + smoothing
  kPerAsrEm,     // paper mode (or no drift filter): one EM rotation per ASR
  kNone,         // odometry as it comes
};

// Laser odometry (localize::ScanOdometry, docs/inputs.md "Laser odometry").
enum class ScanMatch {
  kAuto,  // default mode: when the first scans are dense (localize::ScanDensity); paper mode: never
  kOn,    // always (`--scan-match on`)
  kOff,   // never
};

// The problem with a grid's cell and MHIMM window, "" when none: the cell in
// (0, 10] m, the window from one cell to 100 m ("--cell 0: must be in (0,
// 10] metres"). Shared by cogmap map, grid and vectorize.
std::string CellAndWindowProblem(double cell_m, double window_m);

struct MappingOptions {
  bool paper = false;                  // --mode paper: the thesis's line fit and EM rotation per ASR
  double cell_m = 0.1;                 // grid cell of each room (SPEC 2)
  double window_m = 3.0;               // MHIMM window w (SPEC 2)
  asr::BoundaryMode boundary = asr::BoundaryMode::kDoorway;
  double asr_length_m = 4.5;           // corridor / fixed-length ASR length (thesis 3.1.2)
  double max_asr_m = 15.0;             // default mode: cut a space after this many metres (0 = never)
  double release_confirm_m = 0.0;      // default mode, --door-release: a side released for less travel is a side opening (0: off)
  bool door_gap = false;               // default mode, --door-gap: L and R on when the opening beside the robot is at most 2 close_m wide (asr::BoundaryOptions::gap_m)
  // Default mode, --door-gap-m: that width instead of 2 close_m (implies
  // door_gap; 0: 2 close_m). Doors of 1.6-2.4 m (double doors, open
  // passages) want 2.5; rooms whose furniture leaves gaps of that width
  // between table ends are cut there too (docs/BENCHMARKS.md, "Double doors").
  double door_gap_m = 0.0;
  double direction_split_m = 3.0;      // pose graph, laser walls: direction factors per this much path, tried in Finish (0: off)
  bool cone_hits = false;              // default mode, --sonar-cone: MHIMM over the sonar's cone (grid::MhimmOptions::cone_hits)
  bool cone_walls = true;              // default mode, sonar: the walls kept are a cone grid's (asr::MapperOptions::cone_output_walls); --axis-walls: false
  // Default mode, a sonar ring that looks only forward (sensors::SeesOnlyForward),
  // --cone-orientation: each room's orientation from its cone grid
  // (asr::MapperOptions::orientation_from_cone). Off by default: docs/walls.md,
  // "A ring that looks only forward".
  bool cone_orientation = false;
  bool correct = true;                 // false: every ASR at its odometry pose
  bool pose_graph = true;              // default mode: the pose graph (false: the drift filter)
  bool pre_bend = false;               // pose graph, --pre-bend: the drift it has pinned is removed while the next rooms are mapped
  bool search_closures_again = false;  // pose graph, --search-closures-again (graph::MapOptimizerOptions::search_again)
  // Pose graph: a drift known before the run (rad per metre, CCW), removed
  // inside every room while it is mapped (asr::CognitiveMapper::SetPreBend, lag 0;
  // the graph still estimates the whole drift). `cogmap map`'s second pass
  // sets it to the drift its first pass found (MapJob::second_pass).
  double remove_drift_rad_per_m = 0.0;
  bool drift_filter = true;            // without the graph: the drift-rate filter
  bool smooth = true;                  // drift filter: revise the run's corrections at the end
  double add_drift_rad_per_m = 0.0;    // a systematic heading drift added to the odometry (tests on real logs)
  // A laser robot's odometry corrected by matching each scan against a
  // reference scan (localize::ScanOdometry) before it is mapped; the
  // corrected odometry is what the store keeps as the run's odometry.
  ScanMatch scan_match = ScanMatch::kAuto;
  // Default mode, correcting: the odometry's distance scale. auto (NaN): measured by the
  // range sensors looking along the way (localize::OdometryScaleEstimator) and
  // applied from the next record on as it firms up, shrunk towards 1 under a
  // prior of distance_scale_prior (localize::ShrunkScale); a number: that
  // scale from the start; 1: off. The scaled odometry is the run's odometry
  // in the store (docs/pose-graph.md, "Distance scale").
  double distance_scale = std::numeric_limits<double>::quiet_NaN();
  double distance_scale_prior = 0.01;
  // Default mode: walls as lines in each room's cleaned cells (docs/walls.md);
  // false: the chain pipeline (simplify + fit). Paper mode: always the chains.
  bool wall_lines = false;
  // 2: each closed ASR is vectorised on one of the mapper's threads and
  // placed and stored on another while the next room is mapped
  // (asr::MapperOptions::close_in_background; the same map). 1: everything
  // on the caller's thread.
  int threads = 2;

  // Throws InputError naming the option when a value is out of range.
  void Validate() const;
  Correction correction() const;
};

// What report.json says about one ASR of this run.
struct AsrSummary {
  int id = -1;
  double seconds = 0.0;
  double seconds_grid = 0.0;
  double path_m = 0.0;
  int walls = 0;
  asr::StageBytes bytes;
  double heading_correction_rad = 0.0;  // revised at Finish() when the corrections are
  double pre_bend_rad_per_m = 0.0;      // drift removed while it was mapped (asr::Asr::pre_bend_rad_per_m)
  std::optional<localize::DirectionEstimate> estimate;  // the heading estimate when it closed
  asr::GridOrientation grid_orientation;
};

// The run as a whole, after Finish().
struct RunResult {
  Correction correction = Correction::kNone;
  long records = 0;
  double first_time_s = 0.0;
  double last_time_s = 0.0;
  std::optional<Pose2> world_from_map;  // from the log's ground truth (first record that has it)
  std::vector<AsrSummary> asrs;         // this run's, in closing order
  asr::MapperStats mapper;
  // kPoseGraph. Its per-ASR corrected paths and walls are moved into the
  // store at Finish() (asr::Placement::corrected_path, the ASRs' walls) and
  // left empty here.
  graph::OptimizerResult graph;
  int smoothed = 0;                     // kDriftFilter: ASRs revised by smoothing
  int replayed = 0;                     // --resume: stored ASRs of a run cut short, placed again
  long skipped_records = 0;             // --resume with the stored run's own log: its records already mapped
  // kDriftFilter: the filter's figures.
  double drift_rate_rad_per_m = 0.0;
  double drift_rate_sigma_rad_per_m = 0.0;
  int drift_measurements = 0;
  int drift_rejects = 0;
  double drift_walk_rad_per_sqrt_m = 0.0;
  double drift_sigma_scale = 0.0;
  // kPoseGraph, `cogmap map`'s second pass (MapJob::second_pass): the drift
  // its first pass found, removed inside every room this time (0: one pass),
  // and the first pass's figures.
  double second_pass_drift_removed_rad_per_m = 0.0;
  double first_pass_seconds = 0.0;
  double first_pass_drift_rate_sigma_rad_per_m = 0.0;
  double duration_s() const { return last_time_s - first_time_s; }
  // Laser odometry: whether it ran (kAuto: decided on the first scans'
  // spacing, their mean gap in units of the reference's spacing and how
  // many gaps that was; kOn: whenever the robot has a laser), and its
  // figures (scans == 0 when it did not run).
  bool scan_match_active = false;
  double scan_match_mean_step = 0.0;
  int scan_match_gaps = 0;
  localize::ScanOdometryStats scan_match;
  // The distance scale: measured (estimate.runs == 0 when not), and the one
  // the odometry was scaled by at the end of the run.
  bool distance_scale_measured = false;
  localize::OdometryScaleEstimate distance_scale_estimate;
  double distance_scale_applied = 1.0;
  std::optional<double> distance_scale_carried;  // --resume: the stored run's, driven with until measured
};

// --distance-scale: "auto" (NaN: measured), "off" (1) or a number. Throws
// InputError naming the option for anything else.
double ParseDistanceScale(const std::string& s);

// What the distance scale warns of (report.json distance_scale.warnings and
// the command's warnings): a scale measured far from 1 (a wheel diameter or
// ticks per metre set wrong), and one applied that its evidence barely
// supports.
std::vector<std::string> DistanceScaleWarnings(const RunResult& run);

// What `cogmap map --scan-match` warns of (report.json scan_match.warnings
// and the command's warnings): a robot without a laser, scans farther apart
// on average than the matcher's reference spacing, a tenth or more of the
// scans not matched. Empty without --scan-match.
std::vector<std::string> ScanMatchWarnings(const MappingOptions& options, const RunResult& run);

// "auto", "on" or "off"; and back (InputError naming the value otherwise).
const char* ScanMatchName(ScanMatch m);
ScanMatch ParseScanMatch(const std::string& s);

// Adds a systematic heading drift to odometry (the truth stays): the heading
// turns by an extra rate x the distance driven, and the position follows the
// drifted heading (DriftReintegration from the first pose, as the mapper's
// pre-bend removes one). The distance is counted in step_m steps: a CARMEN
// log's poses (its ODOM lines, and the FLASER lines' poses between them)
// jitter by centimetres from record to record, and summed record by record
// that jitter made "1 deg/m" 1.07-1.13 deg per metre of the
// five CARMEN logs' reference paths (1.02-1.03 now; docs/BENCHMARKS.md,
// "Drift added to real logs").
class DriftAdder {
 public:
  explicit DriftAdder(double rad_per_m, double step_m = 0.1) : rate_(rad_per_m), step_m_(step_m) {}
  Pose2 Add(const Pose2& odom);

 private:
  double rate_;
  double step_m_;
  std::optional<DriftReintegration> drift_;  // from the first pose
};

class MappingPipeline {
 public:
  // 'store' receives every ASR as it closes (one transaction each) and the
  // placements at Finish(); it must outlive the pipeline. A store that already
  // holds a run is continued when Resume() is called before the first Push().
  MappingPipeline(sensors::RobotDescription robot, MappingOptions options, asr::SqliteAsrStore* store);
  ~MappingPipeline();
  MappingPipeline(const MappingPipeline&) = delete;
  MappingPipeline& operator=(const MappingPipeline&) = delete;

  // Continues the stored run: new ASRs take the next ids; the first record's
  // pose is taken to be where the stored run ended.
  void Resume();
  // The log being mapped (io::LogFingerprint) and the records of it skipped
  // before the first Push (a resumed run continuing its own log): stored with
  // every ASR, so that --resume knows where a run of that log stopped.
  void SetLogIdentity(const std::string& fingerprint, long skipped_records) {
    mapper_->SetLogIdentity(fingerprint, skipped_records);
    result_.skipped_records = skipped_records;
  }
  // Called as each ASR closes (after it is stored).
  void OnAsrClosed(std::function<void(const asr::Asr&, const AsrSummary&)> callback);

  void Push(sensors::LogRecord record);
  // Waits for the rooms being closed on the mapper's threads (placed, stored,
  // their OnAsrClosed called): afterwards the store and the summaries agree,
  // for outputs written mid-run. Mapping goes on with the next Push.
  void Settle();
  // Closes the open ASR, places every ASR (the pose graph's final solve or the
  // drift filter's smoothing) and writes the placements into the store.
  const RunResult& Finish();

  int asrs_closed() const { return static_cast<int>(result_.asrs.size()); }
  const sensors::RobotDescription& robot() const { return robot_; }
  const MappingOptions& options() const { return options_; }
  const RunResult& result() const { return result_; }
  // `cogmap map`'s second pass: what its first pass found (RunResult's second_pass fields).
  void NoteSecondPass(double removed_rad_per_m, double first_pass_seconds, double first_pass_sigma_rad_per_m) {
    result_.second_pass_drift_removed_rad_per_m = removed_rad_per_m;
    result_.first_pass_seconds = first_pass_seconds;
    result_.first_pass_drift_rate_sigma_rad_per_m = first_pass_sigma_rad_per_m;
  }
  // The mapper itself (the open room's grid, statistics), read-only.
  const asr::CognitiveMapper& mapper() const { return *mapper_; }

 private:
  void Closed(const asr::Asr& x);
  const localize::DirectionEstimate* LastEstimate() const;
  // Keeps the corrector's estimate for x (LastEstimate, read where it was made:
  // the closing may run on the mapper's second thread) until Closed reports it.
  asr::Asr KeepEstimate(asr::Asr x);
  // The pose graph's pre-bend (asr::CognitiveMapper::SetPreBend): the rate
  // to remove in the rooms mapped next, noted as each ASR is placed (on the
  // placing thread) and read when a room 'lag' later starts.
  void NotePreBend(int asr_id);
  double PreBendAfter(int placed_id);

  sensors::RobotDescription robot_;
  MappingOptions options_;
  asr::SqliteAsrStore* store_;
  localize::HeadingCorrectionOptions heading_options_;
  std::unique_ptr<asr::CognitiveMapper> mapper_;
  localize::HeadingCorrector corrector_;
  localize::DriftHeadingCorrector drift_corrector_;
  std::unique_ptr<graph::MapOptimizer> optimizer_;
  DriftAdder drift_adder_;
  // Laser odometry: the matcher once it runs; with kAuto, the density test
  // and the records held back until it decides (10 scan gaps, about a
  // second of a laser at 10 Hz).
  std::unique_ptr<localize::ScanOdometry> scan_odometry_;
  std::unique_ptr<localize::ScanDensity> scan_density_;
  std::vector<sensors::LogRecord> scan_pending_;
  // The distance scale (MappingOptions::distance_scale): its estimator while
  // measured, and the odometry scaled by it.
  std::unique_ptr<localize::OdometryScaleEstimator> scale_estimator_;
  localize::DistanceScaler scaler_;
  size_t scale_runs_next_ = 1;  // re-estimated when this many runs are in
  void Process(sensors::LogRecord rec);
  void DecideScanMatch();
  // Laser odometry from here on (scan_match auto, decided dense now or by
  // the stored run), with the pose graph's noise model for it.
  void MatchScans();
  std::function<void(const asr::Asr&, const AsrSummary&)> callback_;
  RunResult result_;
  std::mutex estimates_mutex_;
  std::map<int, localize::DirectionEstimate> estimates_;  // ASR id -> its estimate, until reported
  std::mutex pre_bend_mutex_;
  std::map<int, double> pre_bend_after_;  // placed ASR id -> PreBendRate after it, until read
  bool finished_ = false;
};

// The mapper options a MappingOptions implies for a robot (exposed for tools
// that build the mapper themselves, e.g. benchmarks).
asr::MapperOptions MapperOptionsFor(const sensors::RobotDescription& robot, const MappingOptions& options);

// Turns the line extraction of the walls on or off in 'v' and sets its sonar
// blur from the robot's widest beam (docs/walls.md).
void ConfigureWallLines(const sensors::RobotDescription& robot, bool on, vectorize::VectorizeOptions* v);
// True when every range sensor of the robot is a laser.
bool LaserOnly(const sensors::RobotDescription& robot);

}  // namespace cogmap::mapping
